#include "engine.h"
#include "base/log.h"
#include "base/util.h"
#include "scene/light_frustum.h"
#include "scene/scene.h"
#include "techniques/params.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define DEFAULT_CHROMIUM "/usr/bin/chromium"
/* A request's reply line may carry page messages: this is plenty. */
#define REPLY_MAX (1 << 20)

static const char *const output_names[] = {
#define X(id, name) name,
    ENGINE_OUTPUTS(X)
#undef X
};

/* The running driver: its process (a group of its own), its pipes, its
 * folder (the browser's profile, the images it writes). */
static struct {
    pid_t pid;
    pid_t browser;    /* Chromium's (a session of its own), or 0 */
    int in, out;      /* its stdin (we write), its stdout (we read) */
    char *dir;
    char *buf;        /* what has been read of its stdout past the last line */
    size_t len;
    long next_id;
    bool at_exit;     /* engine_shutdown registered */
    bool faulted;
    char *start_failed;  /* why the driver did not start: said again for every later cell, not retried */
    double limit_s;
} drv = {.pid = 0, .in = -1, .out = -1};

static char last_error[1024];

bool engine_faulted(void) { return drv.faulted; }

const char *engine_last_error(void) { return last_error; }

/* Logs the failure's line and keeps it. */
static void fault(const char *line)
{
    snprintf(last_error, sizeof last_error, "%s", line);
    log_error("%s", line);
    drv.faulted = true;
}

void engine_set_time_limit(double seconds) { drv.limit_s = seconds > 0 ? seconds : 0; }

static double time_limit(void) { return drv.limit_s > 0 ? drv.limit_s : ENGINE_TIME_LIMIT_S; }

/* The current cell's deadline (util_now_ms), its browser's start included. */
static double deadline_ms;

static double seconds_left(void) { return fmax(0, (deadline_ms - util_now_ms()) * 1e-3); }

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    return remove(path) == 0 || errno == ENOENT ? 0 : -1;
}

static void remove_tree(const char *dir)
{
    if (dir)
        nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* The last line of the driver's log (its stderr), for a one-line reason;
 * "" when it wrote nothing. malloc'ed. */
static char *driver_log_tail(void)
{
    char *path = util_printf("%s/driver.log", drv.dir), *text = NULL;
    size_t size = 0;
    char *tail = NULL;
    if (util_read_file(path, &text, &size) == 0) {
        while (size > 0 && (text[size - 1] == '\n' || text[size - 1] == '\r'))
            text[--size] = '\0';
        const char *line = strrchr(text, '\n');
        tail = xstrdup(line ? line + 1 : text);
    }
    free(text), free(path);
    return tail ? tail : xstrdup("");
}

/* Whether process pid runs (a zombie, which no one may reap here, does not). */
static bool running(pid_t pid)
{
    char path[64], state = 0;
    snprintf(path, sizeof path, "/proc/%ld/stat", (long)pid);
    FILE *f = kill(pid, 0) == 0 ? fopen(path, "r") : NULL;
    if (f) {
        if (fscanf(f, "%*d (%*[^)]) %c", &state) != 1)
            state = 0;
        fclose(f);
    }
    return f && state != 'Z';
}

void engine_shutdown(void)
{
    if (drv.pid > 0) {
        close(drv.in);  /* the driver closes the browser and exits on end of input */
        drv.in = -1;
        int status;
        pid_t done = 0;
        for (int i = 0; i < 50 && (done = waitpid(drv.pid, &status, WNOHANG)) == 0; i++)
            usleep(100 * 1000);
        /* whatever is left after the driver's own close: the driver's group, and the browser's (a session
         * of its own; its DevTools pipe closed, it exits by itself: this is for one that does not) */
        if (done == 0) {
            kill(-drv.pid, SIGKILL);
            waitpid(drv.pid, &status, 0);
        }
        /* its pipe closed, the browser exits and removes its temporary files; killed, it would leave them */
        for (int i = 0; i < 30 && drv.browser > 0 && running(drv.browser); i++)
            usleep(100 * 1000);
        if (drv.browser > 0)
            kill(-drv.browser, SIGKILL);
        util_child_group(0);
        close(drv.out);
        drv.pid = drv.browser = 0, drv.out = -1;
    }
    remove_tree(drv.dir);
    free(drv.dir), free(drv.buf);
    drv.dir = NULL, drv.buf = NULL, drv.len = 0;
}

/* Reads the driver's next reply line within seconds: the parsed object,
 * or NULL with why set ("over its time limit", "exited", bad JSON). */
static cJSON *read_reply(double seconds, const char **why)
{
    const double deadline = util_now_ms() + seconds * 1e3;
    for (;;) {
        char *nl = drv.buf ? memchr(drv.buf, '\n', drv.len) : NULL;
        if (nl) {
            *nl = '\0';
            cJSON *reply = cJSON_Parse(drv.buf);
            const size_t used = (size_t)(nl - drv.buf) + 1;
            memmove(drv.buf, nl + 1, drv.len - used);
            drv.len -= used;
            if (!reply || !cJSON_IsObject(reply)) {
                cJSON_Delete(reply);
                *why = "its driver wrote a line that is not a JSON object";
                return NULL;
            }
            return reply;
        }
        const double left = deadline - util_now_ms();
        if (left <= 0) {
            *why = "over its time limit";
            return NULL;
        }
        struct pollfd p = {.fd = drv.out, .events = POLLIN};
        const int ready = poll(&p, 1, (int)fmin(left, 1e9) + 1);
        if (ready < 0 && errno == EINTR)
            continue;
        if (ready < 0) {
            *why = "cannot wait for its driver";
            return NULL;
        }
        if (ready == 0)
            continue;
        if (drv.len + 65536 > REPLY_MAX) {
            *why = "its driver's reply is too long";
            return NULL;
        }
        drv.buf = xrealloc(drv.buf, drv.len + 65536);
        const ssize_t n = read(drv.out, drv.buf + drv.len, 65536);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            *why = "its driver exited";
            return NULL;
        }
        drv.len += (size_t)n;
    }
}

/* Why the cell failed, one line: the reason, and the driver's last words
 * where it exited. Stops the driver. */
static void fail(const struct engine_request *r, const char *what, const char *detail)
{
    char *tail = drv.dir ? driver_log_tail() : xstrdup("");
    char *line = util_printf("engine %s, cell %s on %s: %s%s%s%s%s", r->t->engine, r->label, r->scene->name, what,
                             detail && *detail ? ": " : "", detail ? detail : "", *tail ? "; its log says: " : "",
                             tail);
    fault(line);
    free(tail), free(line);
    engine_shutdown();
}

/* The adapters' folder: $SB_ENGINES, else the source tree's engines/. */
static const char *engines_dir(void)
{
    const char *env = getenv("SB_ENGINES");
    return env && *env ? env : SB_SOURCE_DIR "/engines";
}

/* Whether the packages of engines/<folder> are installed (npm ci leaves
 * node_modules/.package-lock.json). */
static bool installed(const char *folder)
{
    char *path = util_printf("%s/%s/node_modules/.package-lock.json", engines_dir(), folder);
    const bool ok = util_file_exists(path);
    free(path);
    return ok;
}

/* Removes the folders of drivers whose harness died without its shutdown
 * (a signal's exit kills the browser but cannot remove a tree):
 * <tmp>/shadowbench-engines.<pid>.* of a pid that no longer runs. */
static void remove_stale(const char *tmp)
{
    DIR *d = opendir(tmp);
    for (struct dirent *e; d && (e = readdir(d));) {
        char *end = NULL;
        if (strncmp(e->d_name, "shadowbench-engines.", 20) != 0)
            continue;
        const long pid = strtol(e->d_name + 20, &end, 10);
        if (pid > 0 && end && *end == '.' && kill((pid_t)pid, 0) != 0 && errno == ESRCH) {
            char *path = util_printf("%s/%s", tmp, e->d_name);
            remove_tree(path);
            free(path);
        }
    }
    if (d)
        closedir(d);
}

/* The browser: $SB_CHROMIUM, else Debian's. */
static const char *chromium_path(void)
{
    const char *env = getenv("SB_CHROMIUM");
    return env && *env ? env : DEFAULT_CHROMIUM;
}

bool engine_installed(const char *engine)
{
    return access(chromium_path(), X_OK) == 0 && installed("driver") && installed(engine);
}

static int start(const struct engine_request *r)
{
    const char *chromium = chromium_path();
    if (access(chromium, X_OK) != 0) {
        char *line = util_printf("engine %s, cell %s on %s: no Chromium at %s (tools/setup installs Debian's "
                                 "chromium; SB_CHROMIUM names another)", r->t->engine, r->label, r->scene->name,
                                 chromium);
        fault(line);
        free(line);
        return -1;
    }
    const char *missing = !installed("driver") ? "driver" : !installed(r->t->engine) ? r->t->engine : NULL;
    if (missing) {
        char *line = util_printf("engine %s, cell %s on %s: the packages of %s/%s are not installed (tools/setup, "
                                 "or npm ci --prefix %s/%s)", r->t->engine, r->label, r->scene->name, engines_dir(),
                                 missing, engines_dir(), missing);
        fault(line);
        free(line);
        return -1;
    }
    const char *env_tmp = getenv("TMPDIR"), *tmp = env_tmp && *env_tmp ? env_tmp : "/tmp";
    remove_stale(tmp);
    drv.dir = util_printf("%s/shadowbench-engines.%ld.XXXXXX", tmp, (long)getpid());
    int to_child[2], from_child[2];
    if (!mkdtemp(drv.dir) || pipe2(to_child, O_CLOEXEC) != 0) {
        fail(r, "cannot make its temporary folder or pipes", strerror(errno));
        return -1;
    }
    if (pipe2(from_child, O_CLOEXEC) != 0) {
        close(to_child[0]), close(to_child[1]);
        fail(r, "cannot make its pipes", strerror(errno));
        return -1;
    }
    char *script = util_printf("%s/driver/driver.mjs", engines_dir()), *log_path = util_printf("%s/driver.log", drv.dir);
    const char *node_env = getenv("SB_NODE");
    const char *node = node_env && *node_env ? node_env : "node";
    const pid_t parent = getpid();
    fflush(NULL);
    const pid_t pid = fork();
    if (pid == 0) {
        /* its own group, which the parent kills as a whole; killed with the parent */
        setpgid(0, 0);
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent)
            _exit(127);
        signal(SIGPIPE, SIG_DFL), signal(SIGXFSZ, SIG_DFL);
        const int log_fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);  /* dup2'd to 2 */
        if (log_fd < 0 || dup2(to_child[0], 0) < 0 || dup2(from_child[1], 1) < 0 || dup2(log_fd, 2) < 0)
            _exit(127);
        execlp(node, node, script, chromium, drv.dir, engines_dir(), (char *)NULL);
        static const char text[] = "cannot run node (Node.js; SB_NODE names another)\n";
        if (write(2, text, sizeof text - 1) < 0)
            _exit(127);
        _exit(127);
    }
    free(script), free(log_path);
    close(to_child[0]), close(from_child[1]);
    if (pid < 0) {
        close(to_child[1]), close(from_child[0]);
        fail(r, "cannot start its driver", strerror(errno));
        return -1;
    }
    setpgid(pid, pid);
    drv.pid = pid, drv.in = to_child[1], drv.out = from_child[0];
    util_child_group(pid);
    if (!drv.at_exit) {
        atexit(engine_shutdown);
        drv.at_exit = true;
    }
    const char *why = NULL;
    cJSON *ready = read_reply(seconds_left(), &why);
    const bool ok = ready && cJSON_IsTrue(cJSON_GetObjectItem(ready, "ok"));
    if (!ok) {
        const char *error = cJSON_GetStringValue(cJSON_GetObjectItem(ready, "error"));
        char *what = util_printf("its browser did not start: %s", error ? error : why);
        fail(r, what, NULL);
        drv.start_failed = what;
        cJSON_Delete(ready);
        return -1;
    }
    const cJSON *browser = cJSON_GetObjectItem(ready, "pid");
    if (cJSON_IsNumber(browser) && browser->valuedouble > 1)
        drv.browser = (pid_t)browser->valuedouble;
    cJSON_Delete(ready);
    return 0;
}

static cJSON *v3_json(struct vec3 v)
{
    const double a[3] = {v.x, v.y, v.z};
    return cJSON_CreateDoubleArray(a, 3);
}

/* The light as the adapters take it: the frustum's eye and axes (rows of
 * its view matrix), its depth range and its window at the near plane; the
 * scene's light itself, for an engine's soft-shadow size: its shape, size
 * (a rect's width and height, a disk's radius, world units; the sun's
 * half-angle, radians) and its size in shadow-map UV (light_frustum.h);
 * and what an engine that fits its own frustum needs to cover
 * shadowbench's: a spot's cone (light_frustum_cone_tan) and the farthest
 * view depth the camera sees. */
static cJSON *light_json(const struct engine_request *r)
{
    const struct light_frustum *f = r->frustum;
    const struct scene_light *sl = &r->scene->light;
    const float *m = f->view.m;
    const struct vec3 x = v3(m[0], m[4], m[8]), y = v3(m[1], m[5], m[9]), z = v3(m[2], m[6], m[10]);
    const struct vec3 eye = v3_scale(v3_add(v3_add(v3_scale(x, m[12]), v3_scale(y, m[13])), v3_scale(z, m[14])), -1);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "kind", f->sun ? "directional" : "spot");
    cJSON_AddItemToObject(o, "eye", v3_json(eye));
    cJSON_AddItemToObject(o, "x", v3_json(x));
    cJSON_AddItemToObject(o, "y", v3_json(y));
    cJSON_AddItemToObject(o, "z", v3_json(z));
    cJSON_AddNumberToObject(o, "near", f->near_world);
    cJSON_AddNumberToObject(o, "far", f->far_world);
    const double window[4] = {f->l, f->r, f->b, f->t};
    cJSON_AddItemToObject(o, "window", cJSON_CreateDoubleArray(window, 4));
    cJSON_AddStringToObject(o, "shape", light_shape_names[sl->shape]);
    if (sl->shape == LIGHT_RECT) {
        const double size[2] = {sl->width, sl->height};
        cJSON_AddItemToObject(o, "size", cJSON_CreateDoubleArray(size, 2));
    } else if (sl->shape == LIGHT_DISK) {
        cJSON_AddNumberToObject(o, "radius", sl->radius);
    } else {
        cJSON_AddNumberToObject(o, "half_angle", sl->half_angle);
    }
    const double size_uv[2] = {f->light_size_uv[0], f->light_size_uv[1]};
    cJSON_AddItemToObject(o, "size_uv", cJSON_CreateDoubleArray(size_uv, 2));
    if (!f->sun)
        cJSON_AddNumberToObject(o, "cone_tan", light_frustum_cone_tan(r->scene, f));
    cJSON_AddNumberToObject(o, "view_far", light_frustum_view_far(r->scene, (float)r->width / (float)r->height));
    return o;
}

static cJSON *request_json(const struct engine_request *r, const char *output)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "id", (double)++drv.next_id);
    cJSON_AddStringToObject(o, "engine", r->t->engine);
    char *scene = realpath(r->scene->path, NULL);
    cJSON_AddStringToObject(o, "scene", scene ? scene : r->scene->path);
    free(scene);
    cJSON_AddNumberToObject(o, "width", r->width);
    cJSON_AddNumberToObject(o, "height", r->height);
    cJSON_AddItemToObject(o, "light", light_json(r));
    cJSON_AddStringToObject(o, "technique", r->t->name);
    cJSON_AddItemToObject(o, "params", params_json(r->t, r->settings));
    cJSON_AddNumberToObject(o, "map_size", r->map_size);
    cJSON_AddNumberToObject(o, "warmup", r->warmup);
    cJSON_AddNumberToObject(o, "frames", r->frames);
    cJSON *outputs = cJSON_AddArrayToObject(o, "outputs");
    for (int k = 0; k < ENGINE_OUTPUT_COUNT; k++)
        if (r->outputs & (1u << k))
            cJSON_AddItemToArray(outputs, cJSON_CreateString(output_names[k]));
    cJSON_AddStringToObject(o, "output", output);
    return o;
}

static int write_all(int fd, const char *s, size_t n)
{
    while (n > 0) {
        const ssize_t w = write(fd, s, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        s += w, n -= (size_t)w;
    }
    return 0;
}

/* The reply's frame times into out's median and quartiles. */
static int take_times(const cJSON *ms, struct engine_result *out)
{
    const int n = cJSON_GetArraySize(ms);
    if (n < 1)
        return -1;
    double *v = xmalloc(sizeof(double) * (size_t)n);
    int k = 0;
    for (const cJSON *e = ms->child; e; e = e->next)
        if (cJSON_IsNumber(e) && isfinite(e->valuedouble) && e->valuedouble >= 0)
            v[k++] = e->valuedouble;
    if (k == n) {
        out->ms = util_quantile(v, n, 0.5);
        out->ms_q1 = util_quantile(v, n, 0.25);
        out->ms_q3 = util_quantile(v, n, 0.75);
    }
    free(v);
    return k == n ? 0 : -1;
}

int engine_render(const struct engine_request *r, struct engine_result *out)
{
    deadline_ms = util_now_ms() + time_limit() * 1e3;
    if (drv.start_failed) {  /* one wait for a browser that does not start, not one a cell */
        fail(r, drv.start_failed, NULL);
        return -1;
    }
    if (drv.pid <= 0 && start(r) != 0)
        return -1;
    char *output = util_printf("%s/cell.f32", drv.dir);
    unlink(output);
    cJSON *req = request_json(r, output);
    const long id = drv.next_id;
    char *line = cJSON_PrintUnformatted(req);
    cJSON_Delete(req);
    const size_t len = strlen(line);
    line = xrealloc(line, len + 2);
    line[len] = '\n', line[len + 1] = '\0';
    const char *why = NULL;
    cJSON *reply = write_all(drv.in, line, len + 1) == 0 ? read_reply(seconds_left(), &why) : NULL;
    free(line);
    if (!reply && !why)
        why = "its driver exited";
    int rc = -1;
    const cJSON *id_item = cJSON_GetObjectItem(reply, "id");
    if (!reply) {
        if (strcmp(why, "over its time limit") == 0) {
            char limit[64];
            snprintf(limit, sizeof limit, "over its time limit of %g s", time_limit());
            fail(r, limit, NULL);
        } else
            fail(r, why, NULL);
    } else if (!cJSON_IsNumber(id_item) || (long)id_item->valuedouble != id)
        fail(r, "its driver answered another request", NULL);
    else if (!cJSON_IsTrue(cJSON_GetObjectItem(reply, "ok")))
        fail(r, cJSON_GetStringValue(cJSON_GetObjectItem(reply, "error")) ?: "failed without a reason", NULL);
    else if (take_times(cJSON_GetObjectItem(reply, "ms"), out) != 0)
        fail(r, "its frame times are not a list of non-negative numbers", NULL);
    else {
        const char *version = cJSON_GetStringValue(cJSON_GetObjectItem(reply, "version")),
                   *renderer = cJSON_GetStringValue(cJSON_GetObjectItem(reply, "renderer"));
        snprintf(out->version, sizeof out->version, "%s", version ? version : "unknown");
        snprintf(out->renderer, sizeof out->renderer, "%s", renderer ? renderer : "unknown");
        const char *notice = cJSON_GetStringValue(cJSON_GetObjectItem(reply, "notice"));
        snprintf(out->notice, sizeof out->notice, "%s", notice ? notice : "");
        const cJSON *ratio = cJSON_GetObjectItem(reply, "texel_ratio");
        for (int k = 0; k < 2; k++) {
            const cJSON *v = cJSON_GetArrayItem(ratio, k);
            out->texel_ratio[k] = cJSON_GetArraySize(ratio) == 2 && cJSON_IsNumber(v) && v->valuedouble > 0 &&
                                          isfinite(v->valuedouble)
                                      ? v->valuedouble
                                      : NAN;
        }
        char *data = NULL;
        size_t size = 0;
        const size_t count = (size_t)r->width * (size_t)r->height;
        int images = 0;
        for (int k = 0; k < ENGINE_OUTPUT_COUNT; k++)
            images += (r->outputs >> k) & 1;
        if (util_read_file(output, &data, &size) != 0 || size != count * sizeof(float) * (size_t)images) {
            char got[96];
            snprintf(got, sizeof got, "%zu bytes, not %d image(s) of %dx%d float32", size, images, r->width,
                     r->height);
            fail(r, "an image of the wrong size", got);
        } else {
            const float *f = (const float *)(const void *)data;
            for (int k = 0, j = 0; k < ENGINE_OUTPUT_COUNT; k++)
                if (r->outputs & (1u << k))
                    memcpy(out->image[k], f + count * (size_t)j++, count * sizeof(float));
            rc = 0;
        }
        free(data);
    }
    cJSON_Delete(reply);
    unlink(output);
    free(output);
    return rc;
}
