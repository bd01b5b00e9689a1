#include "gl_context.h"
#include "gl.h"
#include "gl_backend.h"
#include "base/log.h"

#include <string.h>
#include <sys/resource.h>

static const struct gl_backend_ops *current;
static char platform[64];

int gl_backend_parse(const char *name, enum gl_backend *out)
{
    if (strcmp(name, "osmesa") == 0)
        *out = GL_BACKEND_OSMESA;
    else if (strcmp(name, "egl") == 0)
        *out = GL_BACKEND_EGL;
    else
        return -1;
    return 0;
}

/* Mesa does not survive every refused mapping: under an address-space
 * limit (ulimit -v) llvmpipe dies of SIGSEGV inside OSMesaCreateContextAttribs
 * at 256 MiB, in shader linking at 273 MiB and 512 MiB, in texture
 * allocation at 879 MiB, where it should fail. Every command here that
 * draws succeeded at GL_MIN_ADDRESS_SPACE_MIB, so a lower limit is refused
 * in one line before Mesa is reached. Returns 0 or -1 (logged). */
static int check_address_space(void)
{
    struct rlimit as;
    if (getrlimit(RLIMIT_AS, &as) != 0 || as.rlim_cur == RLIM_INFINITY ||
        as.rlim_cur >= (rlim_t)GL_MIN_ADDRESS_SPACE_MIB << 20)
        return 0;
    log_error("OpenGL: the address-space limit (ulimit -v %llu KiB) is below the %d MiB shadowbench needs: under "
              "it Mesa crashes rather than failing; raise or lift the limit", (unsigned long long)(as.rlim_cur >> 10),
              GL_MIN_ADDRESS_SPACE_MIB);
    return -1;
}

int gl_context_create(enum gl_backend backend)
{
    static const struct gl_backend_ops *const backends[] = {
        [GL_BACKEND_OSMESA] = &gl_backend_osmesa, [GL_BACKEND_EGL] = &gl_backend_egl, [GL_BACKEND_GLFW] = &gl_backend_glfw};
    const struct gl_backend_ops *ops = backends[backend];
    if (check_address_space() != 0 || ops->create(platform, sizeof platform) != 0)
        return -1;
    current = ops;
    if (!gl_load(ops->getproc, false)) {
        gl_context_destroy();
        return -1;
    }
    gl_install_debug_output();
    /* Reversed Z in [0, 1] for every depth buffer: near = 1, far = 0, so
     * float depth keeps its precision where perspective needs it. */
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_GREATER);
    glEnable(GL_DEPTH_TEST);
    log_debug("OpenGL: %s, %s, %s, through %s", gl_context_renderer(), gl_context_vendor(), gl_context_version(),
              platform);
    return 0;
}

bool gl_context_load_test_functions(void)
{
    return current && gl_load(current->getproc, true);
}

void gl_context_destroy(void)
{
    if (current)
        current->destroy();
    current = NULL;
}

static const char *gl_string(GLenum name)
{
    const char *s = current ? (const char *)glGetString(name) : NULL;
    return s ? s : "none";
}

const char *gl_context_renderer(void)
{
    return gl_string(GL_RENDERER);
}

const char *gl_context_vendor(void)
{
    return gl_string(GL_VENDOR);
}

const char *gl_context_version(void)
{
    return gl_string(GL_VERSION);
}

const char *gl_context_platform(void)
{
    return current ? platform : "none";
}

bool gl_context_is_cpu(void)
{
    const char *r = gl_context_renderer();
    return strstr(r, "llvmpipe") || strstr(r, "softpipe") || strstr(r, "swrast");
}
