#include "shader.h"
#include "base/log.h"
#include "base/util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *dir;

int shader_init(const char *override)
{
    dir = util_find_dir(override, "SHADOWBENCH_SHADERS", "shaders", "shadow_common.glsl");
    return dir ? 0 : -1;
}

char *shader_path(const char *file)
{
    return util_printf("%s/%s", dir, file);
}

/* Files of one composed source: GLSL `#line L N` can only carry a number N,
 * so N indexes this table and errors are mapped back through it. */
#define MAX_FILES 16
struct composition {
    const char *files[MAX_FILES];
    int count;
    struct strbuf text;
};

static int compose(struct composition *c, const char *file, const char *defines, int depth);

static int file_index(struct composition *c, const char *file)
{
    for (int i = 0; i < c->count; i++)
        if (strcmp(c->files[i], file) == 0)
            return i;
    if (c->count == MAX_FILES)
        return -1;
    c->files[c->count] = xstrdup(file);
    return c->count++;
}

/* Appends `file` to c->text, expanding #include lines (each file once). */
static int compose(struct composition *c, const char *file, const char *defines, int depth)
{
    int already = c->count;
    int index = file_index(c, file);
    if (index < 0) {
        log_error("%s/%s: too many included files (at most %d)", dir, file, MAX_FILES);
        return -1;
    }
    if (index < already && depth > 0)
        return 0; /* included before: include-once */
    if (c->text.len > 0)
        strbuf_printf(&c->text, "#line 1 %d\n", index);
    char *path = util_printf("%s/%s", dir, file), *src;
    size_t size;
    int err = util_read_file(path, &src, &size);
    if (err) {
        log_error("%s: cannot read shader: %s", path, util_read_error(err));
        free(path);
        return -1;
    }
    int line_no = 0, rc = 0;
    for (char *line = src, *nl; line && !rc; line = nl ? nl + 1 : NULL) {
        nl = strchr(line, '\n');
        if (nl)
            *nl = '\0';
        line_no++;
        char inc[256];
        if (c->text.len == 0 && strncmp(line, "#version", 8) == 0) {
            strbuf_printf(&c->text, "%s\n%s#line 2 %d\n", line, defines ? defines : "", index);
        } else if (sscanf(line, " #include \"%255[^\"]\"", inc) == 1) {
            if (depth > 8) {
                log_error("%s:%d: includes nest deeper than 8", path, line_no);
                rc = -1;
                break;
            }
            rc = compose(c, inc, NULL, depth + 1);
            strbuf_printf(&c->text, "#line %d %d\n", line_no + 1, index);
        } else {
            strbuf_printf(&c->text, "%s\n", line);
        }
    }
    free(src);
    free(path);
    return rc;
}

/* Rewrites Mesa's "N:L(C): message" log lines as "<file>:L:C: message". */
static void log_shader_errors(const struct composition *c, const char *label, const char *info)
{
    char *copy = xstrdup(info), *save = NULL;
    for (char *line = strtok_r(copy, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        int n, l, col, off = 0;
        if (sscanf(line, "%d:%d(%d): %n", &n, &l, &col, &off) == 3 && off > 0 && n >= 0 && n < c->count)
            log_error("%s/%s:%d:%d: %s", dir, c->files[n], l, col, line + off);
        else
            log_error("%s: %s", label, line);
    }
    free(copy);
}

static void composition_free(struct composition *c)
{
    for (int i = 0; i < c->count; i++)
        free((char *)c->files[i]);
    strbuf_free(&c->text);
}

/* The info log of a shader or (program) a program; malloc'ed. */
static char *info_log(GLuint object, bool program)
{
    GLint len = 0;
    (program ? glGetProgramiv : glGetShaderiv)(object, GL_INFO_LOG_LENGTH, &len);
    char *info = xcalloc((size_t)len + 1, 1);
    (program ? glGetProgramInfoLog : glGetShaderInfoLog)(object, len, NULL, info);
    return info;
}

static GLuint compile_stage(const char *label, const char *defines, const struct shader_stage *st)
{
    struct composition c = {0};
    for (int i = 0; i < 3 && st->files[i]; i++)
        if (compose(&c, st->files[i], defines, 0) != 0) {
            composition_free(&c);
            return 0;
        }
    GLuint sh = glCreateShader(st->type);
    const char *text = c.text.data;
    glShaderSource(sh, 1, &text, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char *info = info_log(sh, false);
        log_error("%s: %s does not compile:", label, st->files[0]);
        log_shader_errors(&c, label, info);
        free(info);
        glDeleteShader(sh);
        sh = 0;
    } else {
        char *name = util_printf("%s: %s", label, st->files[0]);
        gl_label(GL_SHADER, sh, name);
        free(name);
    }
    composition_free(&c);
    return sh;
}

GLuint shader_program(const char *label, const char *defines, const struct shader_stage *stages,
                      int stage_count)
{
    GLuint prog = glCreateProgram();
    GLuint shaders[4] = {0};
    bool ok = stage_count <= 4;
    for (int i = 0; i < stage_count && ok; i++) {
        shaders[i] = compile_stage(label, defines, &stages[i]);
        ok = shaders[i] != 0;
        if (ok)
            glAttachShader(prog, shaders[i]);
    }
    if (ok) {
        glLinkProgram(prog);
        GLint linked = 0;
        glGetProgramiv(prog, GL_LINK_STATUS, &linked);
        if (!linked) {
            char *info = info_log(prog, true);
            log_error("%s: program does not link: %s", label, info);
            free(info);
            ok = false;
        }
    }
    for (int i = 0; i < stage_count && i < 4; i++)
        if (shaders[i])
            glDeleteShader(shaders[i]);
    if (!ok) {
        glDeleteProgram(prog);
        return 0;
    }
    gl_label(GL_PROGRAM, prog, label);
    return prog;
}
