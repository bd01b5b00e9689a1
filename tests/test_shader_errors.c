/* Protects STYLE.md items 8 and 10: a GLSL error inside an #include'd file
 * is reported with that file's path and its own line number, not the line of
 * the composed source; a clean composition of several files links; GL errors
 * reach our log through the debug-output callback, with no check at the call. */
#include "check.h"
#include "run_cmd.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "gl/shader.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[] = "/tmp/sb_test_shader_XXXXXX";

static void put(const char *name, const char *text)
{
    char *p = util_printf("%s/%s", dir, name);
    util_write_file_atomic(p, text, strlen(text));
    free(p);
}

static int saved_stderr;
static char *stderr_path;

static void capture_begin(void)
{
    stderr_path = util_printf("%s/stderr.txt", dir);
    fflush(stderr);
    saved_stderr = dup(2);
    int fd = open(stderr_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 2);
    close(fd);
}

static void capture_end(struct strbuf *log)
{
    fflush(stderr);
    dup2(saved_stderr, 2);
    close(saved_stderr);
    char *text = NULL;
    size_t size;
    if (util_read_file(stderr_path, &text, &size) == 0)
        strbuf_append(log, text, size);
    free(text);
    free(stderr_path);
}

/* Compiles with stderr captured; returns the program and the log text. */
static GLuint compile_capturing(const char *file, struct strbuf *log)
{
    capture_begin();
    GLuint p = shader_program("test program", "#define FROM_DEFINES 1.0\n",
                              (const struct shader_stage[]){{GL_VERTEX_SHADER, {"pass.vert"}},
                                                            {GL_FRAGMENT_SHADER, {file, "tail.glsl"}}},
                              2);
    capture_end(log);
    return p;
}

int main(void)
{
    if (!mkdtemp(dir))
        return 1;
    put("shadow_common.glsl", "// probe file for the shaders folder\n");
    put("pass.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n");
    put("helpers.glsl", "// helpers\n\nfloat helper() { return FROM_DEFINES; }\n");
    put("broken_inc.glsl", "// line 1\n// line 2\nfloat broken() { return undefined_name; }\n");
    put("good.frag", "#version 450 core\n#include \"helpers.glsl\"\n#include \"helpers.glsl\"\n"
                     "out vec4 c;\nfloat tail();\nvoid main() { c = vec4(helper() + tail()); }\n");
    put("bad.frag", "#version 450 core\n#include \"helpers.glsl\"\n#include \"broken_inc.glsl\"\n"
                    "out vec4 c;\nfloat tail();\nvoid main() { c = vec4(broken() + tail()); }\n");
    put("tail.glsl", "float tail() { return helper(); }\n");
    if (gl_context_create(GL_BACKEND_OSMESA) != 0 || shader_init(dir) != 0) {
        CHECK(false, "GL context");
        return check_finish();
    }

    struct strbuf log = {0};
    GLuint good = compile_capturing("good.frag", &log);
    CHECK(good != 0, "include-once, defines and a second file in the stage must link: %s",
          log.data ? log.data : "");
    strbuf_free(&log);

    GLuint bad = compile_capturing("bad.frag", &log);
    CHECK(bad == 0, "an undefined name must not compile");
    char *want = util_printf("%s/broken_inc.glsl:3:", dir);
    CHECK(log.data && strstr(log.data, want), "the error must name %s (the included file, line 3), "
          "got:\n%s", want, log.data ? log.data : "");
    free(want);
    strbuf_free(&log);

    /* An invalid enum: reported by the driver through our callback. */
    capture_begin();
    glEnable(0x7fff);
    capture_end(&log);
    CHECK(log.data && strstr(log.data, "shadowbench: error: OpenGL (api"),
          "GL errors must reach the log, got: %s", log.data ? log.data : "(nothing)");
    strbuf_free(&log);

    gl_context_destroy();
    remove_tree(dir);
    return check_finish();
}
