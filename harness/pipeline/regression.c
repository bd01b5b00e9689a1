#include "regression.h"
#include "base/log.h"
#include "base/util.h"
#include "score/tuned.h"
#include "techniques/params.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* "pcf@radius_texels=8,pattern=grid" -> technique and settings (defaults
 * plus the values); "pcss@seed003" -> a preset's; "pcf@tuned" -> pcf's
 * tuned settings for scene s (from tuned_dir). Returns 0 or -1 (logged). */
static int parse_label(const char *label, const struct scene *s, const char *tuned_dir,
                       const struct technique **t, void **settings)
{
    for (const char *p = label; *p; p++)
        if ((unsigned char)*p < 32 || *p == '/' || *p == 127) {
            log_error("not a cell name: it holds a control character or '/'");
            return -1;
        }
    const char *at = strchr(label, '@');
    char name[64];
    snprintf(name, sizeof name, "%.*s", at ? (int)(at - label) : (int)strlen(label), label);
    if (!(*t = technique_find(name))) {
        log_error("cell '%s': unknown technique '%s'", label, name);
        return -1;
    }
    if (at && strcmp(at, TUNED_SUFFIX) == 0) {
        struct tuned tu;
        const enum tuned_load_result rc = tuned_load(tuned_dir, *t, &tu);
        if (rc == TUNED_NONE)
            log_error("cell '%s': %s/%s.json does not exist", label, tuned_dir, (*t)->name);
        if (rc != TUNED_LOADED)
            return -1;
        *settings = memcpy(xmalloc((*t)->settings_size), tuned_settings(&tu, s), (*t)->settings_size);
        tuned_free(&tu);
        return 0;
    }
    *settings = params_defaults(*t);
    const struct technique_preset *preset = at ? technique_preset_find(*t, at + 1) : NULL;
    int rc = at ? params_apply(*t, *settings, preset ? preset->params : at + 1, label) : 0;
    if (!rc)
        rc = params_check(*t, *settings);
    if (rc) {
        free(*settings);
        *settings = NULL;
    }
    return rc;
}

static bool known_cell(const struct regression *r, const struct scene *s, const char *label)
{
    for (int i = 0; i < r->count; i++)
        if (r->cells[i].scene == s && strcmp(r->cells[i].label, label) == 0)
            return true;
    return false;
}

/* Adds cell `label` of scene s (when its technique is selected and it is
 * not there yet). Returns 0 or -1 (logged). */
static int add_cell(struct regression *r, const struct technique *const *techniques, int technique_count,
                    const struct scene *s, const char *label, bool declared)
{
    const struct technique *t;
    void *settings;
    if (known_cell(r, s, label))
        return 0;
    char name[64];  /* a technique not selected: its cells are not read (a tuned one needs its file) */
    snprintf(name, sizeof name, "%.*s", (int)strcspn(label, "@"), label);
    if ((t = technique_find(name)) && !technique_in(techniques, technique_count, t))
        return 0;
    if (parse_label(label, s, r->tuned_dir, &t, &settings) != 0)
        return -1;
    if (r->count == r->capacity) {
        r->capacity = r->capacity ? 2 * r->capacity : 64;
        r->cells = xrealloc(r->cells, (size_t)r->capacity * sizeof *r->cells);
    }
    struct regression_cell *c = &r->cells[r->count++];
    *c = (struct regression_cell){.scene = s, .label = xstrdup(label), .t = t, .label_settings = settings,
                                  .declared = declared, .setup = baseline_setup_default};
    c->settings = memcpy(xmalloc(t->settings_size), settings, t->settings_size);
    c->json_path = regression_file(r->baselines_dir, c, "json");
    c->png_path = regression_file(r->baselines_dir, c, "png");
    return 0;
}

char *regression_file(const char *dir, const struct regression_cell *c, const char *ext)
{
    return util_printf("%s/%s/%s.%s", dir, c->scene->name, c->label, ext);
}

/* The baseline files under <baselines>/<scene>/ (their stems), in name
 * order. */
static int add_files(struct regression *r, const struct technique *const *techniques, int technique_count,
                     const struct scene *s)
{
    char *dir = util_printf("%s/%s", r->baselines_dir, s->name);
    struct dirent **names = NULL;
    const int n = scandir(dir, &names, NULL, alphasort);
    int rc = 0;
    for (int i = 0; i < n; i++) {
        const size_t len = strlen(names[i]->d_name);
        if (!rc && len > 5 && strcmp(names[i]->d_name + len - 5, ".json") == 0) {
            char *path = util_printf("%s/%s", dir, names[i]->d_name);
            names[i]->d_name[len - 5] = '\0';
            log_set_context(path);
            rc = add_cell(r, techniques, technique_count, s, names[i]->d_name, false);
            log_set_context(NULL);
            free(path);
        }
        free(names[i]);
    }
    free(names);
    free(dir);
    return rc;
}

int regression_collect(struct regression *r, const struct scene *scenes, int scene_count,
                       const struct technique *const *techniques, int technique_count)
{
    for (int s = 0; s < scene_count; s++) {
        for (int i = 0; i < technique_count; i++) {
            const struct technique *t = techniques[i];
            char *tuned = util_printf("%s/%s.json", r->tuned_dir, t->name),
                 *label = util_printf("%s" TUNED_SUFFIX, t->name);
            const int rc = add_cell(r, techniques, technique_count, &scenes[s], t->name, false) ||
                           (util_file_exists(tuned) &&
                            add_cell(r, techniques, technique_count, &scenes[s], label, false));
            free(tuned), free(label);
            if (rc)
                return -1;
        }
        for (int i = 0; i < technique_count; i++)  /* the presets, as the run has them */
            for (const struct technique_preset *p = techniques[i]->presets; p && p->name; p++) {
                char *label = util_printf("%s@%s", techniques[i]->name, p->name);
                const int rc = add_cell(r, techniques, technique_count, &scenes[s], label, false);
                free(label);
                if (rc)
                    return -1;
            }
        /* in registry order, whatever the order of the selection */
        for (const struct technique *const *t = technique_list; *t; t++)
            for (const struct technique_cell *d = (*t)->regression; d && d->scene; d++)
                for (int k = 0; k < TECHNIQUE_CELLS_PER_SCENE && d->params[k] && !strcmp(d->scene, scenes[s].name);
                     k++) {
                    char *label = util_printf("%s@%s", (*t)->name, d->params[k]);
                    const int rc = add_cell(r, techniques, technique_count, &scenes[s], label, true);
                    free(label);
                    if (rc)
                        return -1;
                }
        if (add_files(r, techniques, technique_count, &scenes[s]) != 0)
            return -1;
    }
    return 0;
}

int regression_read(struct regression_cell *c)
{
    if (baseline_read(c->json_path, c->png_path, c->scene->name, c->label, c->t, &c->base, c->settings) != 0)
        return -1;
    if (c->base.doc)
        c->setup = c->base.setup;
    return 0;
}

int regression_render(struct scene_setup *ss, struct regression_cell *c)
{
    c->now = (struct metrics){0};
    if (scene_setup_cell(ss, c->t, c->settings, &c->now) != 0)
        return -1;
    const size_t count = (size_t)c->setup.width * (size_t)c->setup.height;
    free(c->v);
    c->v = memcpy(xmalloc(count * sizeof(float)), ss->v, count * sizeof(float));
    return 0;
}

static bool same_params(const struct technique *t, const void *a, const void *b)
{
    for (const struct technique_param *p = t->params; p->name; p++) {
        char x[64], y[64];
        params_value_text(t, a, p->name, x, sizeof x);
        params_value_text(t, b, p->name, y, sizeof y);
        if (strcmp(x, y) != 0)
            return false;
    }
    return true;
}

bool regression_params_current(const struct regression_cell *c)
{
    return same_params(c->t, c->settings, c->label_settings);
}

int regression_idle_params(struct scene_setup *ss, const struct regression_cell *c, struct regression_param *out,
                           int max)
{
    const size_t count = (size_t)c->setup.width * (size_t)c->setup.height;
    int n = 0;
    void *defaults = params_defaults(c->t);
    for (const struct technique_param *p = c->t->params; p->name; p++) {
        char mine[64], def[64];
        params_value_text(c->t, c->settings, p->name, mine, sizeof mine);
        params_value_text(c->t, defaults, p->name, def, sizeof def);
        if (strcmp(mine, def) == 0)
            continue;
        void *back = memcpy(xmalloc(c->t->settings_size), c->settings, c->t->settings_size);
        params_set(c->t, back, p->name, def);
        char why[256];
        const bool allowed = !c->t->check || c->t->check(back, why, sizeof why) == 0;
        struct metrics m = {0};
        if (allowed && scene_setup_cell(ss, c->t, back, &m) == 0 &&
            memcmp(ss->v, c->v, count * sizeof(float)) == 0 && n < max) {
            out[n] = (struct regression_param){c->t, p, ""};
            snprintf(out[n++].def, sizeof out->def, "%s", def);
        }
        free(back);
    }
    free(defaults);
    return n;
}

int regression_uncovered(const struct regression *r, const struct technique *const *techniques,
                         int technique_count, struct regression_param *out, int max)
{
    int missing = 0;
    for (int i = 0; i < technique_count; i++) {
        const struct technique *t = techniques[i];
        void *defaults = params_defaults(t);
        for (const struct technique_param *p = t->params; p->name; p++) {
            char def[64], mine[64];
            params_value_text(t, defaults, p->name, def, sizeof def);
            bool set = false;
            for (int c = 0; c < r->count && !set; c++)
                if (r->cells[c].declared && r->cells[c].t == t) {
                    params_value_text(t, r->cells[c].label_settings, p->name, mine, sizeof mine);
                    set = strcmp(mine, def) != 0;
                }
            if (!set && missing < max) {
                out[missing] = (struct regression_param){t, p, ""};
                snprintf(out[missing++].def, sizeof out->def, "%s", def);
            }
        }
        free(defaults);
    }
    return missing;
}

void regression_free(struct regression *r)
{
    for (int i = 0; i < r->count; i++) {
        struct regression_cell *c = &r->cells[i];
        free(c->label), free(c->settings), free(c->label_settings);
        free(c->json_path), free(c->png_path), free(c->v);
        baseline_free(&c->base);
    }
    free(r->cells);
    r->cells = NULL;
    r->count = r->capacity = 0;
}
