/* What every command does the same way before its work. */
#include "cli.h"
#include "gl/shader.h"
#include "output/out_dir.h"
#include "scene/catalog.h"

int cli_load_scenes(const struct options *o, const char *const *defaults, int default_count, struct scene *scenes,
                    int *count)
{
    const bool named = o->scene_count > 0;
    return catalog_load(named ? o->scenes : defaults, named ? o->scene_count : default_count, output_files, scenes,
                        CLI_MAX_SCENES, count);
}

int cli_gl_open(const struct options *o, enum gl_backend backend)
{
    /* a bad --shaders is bad usage; so is a context that cannot be made here */
    return shader_init(o->shader_dir) != 0 || gl_context_create(backend) != 0 ? -1 : 0;
}
