/* Protects `hard` where its model is exact: under a near-point light (1 mm
 * wide, so the true penumbra is ~1 mm, far below a pixel) the truth is a step
 * and one depth comparison per pixel is right everywhere except for aliasing
 * at the edge. Every wrong pixel (|e| > 0.5) must lie within 2 px of the
 * ground truth's edge: a shadow-map texel here is about one screen pixel, so
 * the comparison can flip at most the pixels the edge's texels cover. */
#include "check.h"
#include "parallel_planes.h"
#include "run_cmd.h"
#include "base/image.h"

#include <string.h>

#define W 128
#define H 128

static char dir[] = "/tmp/sb_test_hard_XXXXXX";

static bool near_edge(const float *v, const float *mask, int x, int y)
{
    bool lo = false, hi = false;
    for (int dy = -2; dy <= 2; dy++)
        for (int dx = -2; dx <= 2; dx++) {
            int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= W || yy >= H || mask[yy * W + xx] < 0.5f)
                continue;
            lo |= v[yy * W + xx] < 0.5f;
            hi |= v[yy * W + xx] >= 0.5f;
        }
    return lo && hi;
}

int main(int argc, char **argv)
{
    if (argc < 2 || !mkdtemp(dir))
        return 1;
    char *scene = util_printf("%s/point_light.gltf", dir);
    write_parallel_planes(scene, 0.001f, false);
    char *cmd = util_printf("%s run --scene %s --technique hard --width %d --height %d --gt-samples 16 "
                            "--shadow-map-size 2048 --frames 1 --no-cache -q --out %s/out",
                            argv[1], scene, W, H, dir);
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 0, "run exit %d: %s", status, err.data);

    char *gt_path = util_printf("%s/out/point_light/groundtruth.exr", dir);
    char *v_path = util_printf("%s/out/point_light/hard/visibility.exr", dir);
    struct exr_channel gt[] = {{"V", NULL}, {"mask", NULL}}, v[] = {{"V", NULL}};
    const bool have = image_read_exr(gt_path, W, H, gt, 2, NULL) == 0 && image_read_exr(v_path, W, H, v, 1, NULL) == 0;
    CHECK(have, "%s or %s cannot be read", gt_path, v_path);  /* unreadable is a failure, never a pass */
    if (have) {
        int lit = 0, umbra = 0, wrong = 0, wrong_far = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                int i = y * W + x;
                if (gt[1].data[i] < 0.5f)
                    continue;
                lit += v[0].data[i] == 1.0f && gt[0].data[i] == 1.0f;
                umbra += v[0].data[i] == 0.0f && gt[0].data[i] == 0.0f;
                if (fabsf(v[0].data[i] - gt[0].data[i]) > 0.5f) {
                    wrong++;
                    wrong_far += !near_edge(gt[0].data, gt[1].data, x, y);
                }
            }
        printf("hard under a point-like light: %d lit, %d umbra, %d wrong pixels (%d far from the "
               "edge)\n", lit, umbra, wrong, wrong_far);
        CHECK(lit > 1000 && umbra > 1000, "both sides of the edge must be in view");
        CHECK(wrong_far == 0, "%d wrong pixels away from the edge (acne or leaks)", wrong_far);
    } else {
        CHECK(false, "outputs missing");
    }
    free(gt[0].data), free(gt[1].data), free(v[0].data);
    free(gt_path), free(v_path), free(cmd), free(scene);
    strbuf_free(&err);
    remove_tree(dir);
    return check_finish();
}
