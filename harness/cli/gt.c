/* shadowbench gt: one scene's ground truth into an EXR, and its noise
 * floor. */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "output/cell_output.h"
#include "output/out_dir.h"
#include "truth/groundtruth.h"

#include <stdio.h>
#include <stdlib.h>

int gt_main(const struct options *o)
{
    struct scene s;
    int count = 0;
    struct light_frustum f;
    if (cli_load_scenes(o, NULL, 0, &s, 1, &count) != 0 || light_frustum_fit(&s, (float)o->width / (float)o->height, &f) != 0) {
        if (count)
            scene_free(&s);
        return EXIT_USAGE;
    }
    char *dir = util_printf("%s/%s", o->out_dir, s.name);
    /* --out itself is claimed (a run writing there holds it), then
     * <out>/<scene>, which may not be a link out of it */
    if (out_dir_claim(o->out_dir) != 0 || util_mkdirs_own(dir, 1) != 0) {
        free(dir);
        scene_free(&s);
        return EXIT_USAGE;
    }
    struct gt_image gt;
    int status = EXIT_CHECK_FAILED;
    if (gt_obtain(&s, &f, &(struct gt_desc){.width = o->width, .height = o->height, .samples = o->gt_samples},
                  o->cache_dir, &gt) == 0) {
        /* No GL pass here: the mask lacks run's silhouette check (docs/design.md §6). */
        const size_t pixels = (size_t)o->width * (size_t)o->height;
        size_t scored = 0;
        for (size_t i = 0; i < pixels; i++)
            scored += gt.mask[i] > 0;
        if (!scored)  /* as run says of an unscored cell; a noise floor of nothing is no number */
            log_error("%s: no pixel to score: the camera sees no surface inside the light's frustum that sees "
                      "the light above its horizon", s.path);
        else if (output_groundtruth(dir, &gt, gt.mask) == 0) {
            printf("%s/%s\nnoise floor (rms error of V at %d samples): %.5f\n", dir, cell_files[CELL_GROUNDTRUTH_EXR],
                   o->gt_samples,
                   gt_noise_floor(gt.noise, gt.mask, pixels));
            status = EXIT_OK;
        }
        gt_image_free(&gt);
    }
    free(dir);
    scene_free(&s);
    return status;
}
