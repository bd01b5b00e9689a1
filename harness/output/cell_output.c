#include "cell_output.h"
#include "picture.h"
#include "base/image.h"
#include "base/util.h"

#include <stdlib.h>

const char *const cell_files[CELL_FILE_COUNT] = {
#define X(id, name) name,
    CELL_FILES(X)
#undef X
};

/* <dir>/<file>: V in grey, unscored pixels hatched where scored is given. */
static int write_visibility_png(const char *dir, enum cell_file file, const float *v, const float *distance,
                                const float *scored, int w, int h)
{
    struct picture p;
    picture_visibility(v, distance, scored, w, h, &p);
    char *path = util_printf("%s/%s", dir, cell_files[file]);
    int rc = image_write_png(path, p.width, p.height, p.rgb);
    free(path);
    picture_free(&p);
    return rc;
}

int output_cell_images(const char *dir, const struct cell_images *im)
{
    const int w = im->width, h = im->height;
    size_t count = (size_t)w * (size_t)h;
    float *error = xmalloc(sizeof(float) * count);
    for (size_t i = 0; i < count; i++)
        error[i] = im->scored[i] > 0.5f ? im->v[i] - im->v_gt[i] : 0.0f;
    char *vis_exr = util_printf("%s/%s", dir, cell_files[CELL_VISIBILITY_EXR]),
         *err_exr = util_printf("%s/%s", dir, cell_files[CELL_ERROR_EXR]),
         *heat = util_printf("%s/%s", dir, cell_files[CELL_HEATMAP_PNG]);
    struct picture hm;
    picture_error_heatmap(im->v, im->v_gt, im->scored, w, h, &hm);
    int rc = util_mkdirs_own(dir, 2) ||  /* <scene>/<cell> */
             image_write_exr(vis_exr, w, h, &(struct exr_channel){"V", (float *)im->v}, 1, NULL) ||
             image_write_exr(err_exr, w, h, &(struct exr_channel){"E", error}, 1, NULL) ||
             write_visibility_png(dir, CELL_VISIBILITY_PNG, im->v, im->distance, NULL, w, h) ||
             image_write_png(heat, hm.width, hm.height, hm.rgb);
    picture_free(&hm);
    free(vis_exr), free(err_exr), free(heat), free(error);
    return rc ? -1 : 0;
}

int output_cell_metrics(const char *dir, const struct cell *c)
{
    char *json = util_printf("%s/%s", dir, cell_files[CELL_METRICS_JSON]);
    cJSON *mj = report_cell_json(c);
    int rc = report_write_json(json, mj);
    cJSON_Delete(mj);
    free(json);
    return rc;
}

int output_groundtruth(const char *dir, const struct gt_image *gt, const float *mask)
{
    char *path = util_printf("%s/%s", dir, cell_files[CELL_GROUNDTRUTH_EXR]);
    struct exr_channel ch[] = {{"V", gt->v}, {"V_weighted", gt->v_weighted}, {"H", gt->h},
                               {"E", gt->e}, {"mask", (float *)mask}};
    int rc = image_write_exr(path, gt->width, gt->height, ch, 5, NULL) ||
             write_visibility_png(dir, CELL_GROUNDTRUTH_PNG, gt->v, gt->distance, mask, gt->width, gt->height);
    free(path);
    return rc ? -1 : 0;
}
