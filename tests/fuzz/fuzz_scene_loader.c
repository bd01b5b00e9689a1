/* libFuzzer target for the scene loader (docs/tests.md, fuzzing): each
 * input is written to a file (.glb when it starts with "glTF", else
 * .gltf) and loaded; ASan and UBSan watch. The loader must return an error
 * or a scene, never crash, hang or leak. Built only by -DSB_FUZZ=ON with
 * clang (tests/test_fuzz.sh); the seed corpus is scenes/. */
#include "base/log.h"
#include "scene/scene.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char path[64];
    const char *ext = size >= 4 && memcmp(data, "glTF", 4) == 0 ? "glb" : "gltf";
    snprintf(path, sizeof path, "/tmp/sb_fuzz_%ld.%s", (long)getpid(), ext);
    FILE *f = fopen(path, "wb");
    if (!f)
        return 0;
    fwrite(data, 1, size, f);
    fclose(f);
    log_set_level(LOG_NONE);  /* every rejected input would print its line */
    struct scene s;
    if (scene_load(path, &s) == 0)
        scene_free(&s);
    unlink(path);
    return 0;
}
