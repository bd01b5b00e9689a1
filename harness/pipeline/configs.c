#include "configs.h"
#include "score/tuned.h"
#include "base/log.h"
#include "base/util.h"
#include "techniques/params.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One --sweep T.P=v1,...,vn, its values checked and spelled as the outputs
 * spell them. */
struct sweep {
    const struct technique *t;
    char param[64];
    char **values;
    int count;
};

static void sweep_clear(struct sweep *s)
{
    for (int i = 0; i < s->count; i++)
        free(s->values[i]);
    free(s->values);
}

static int parse_sweep(const struct config_desc *o, const char *arg, const struct sweep *done,
                       int done_count, struct sweep *s)
{
    const char *dot = strchr(arg, '.'), *eq = strchr(arg, '=');
    memset(s, 0, sizeof *s);
    if (!dot || !eq || eq < dot || !eq[1]) {
        log_error("--sweep: '%s' is not technique.parameter=value,value,...", arg);
        return -1;
    }
    char tech[64];
    snprintf(tech, sizeof tech, "%.*s", (int)(dot - arg), arg);
    snprintf(s->param, sizeof s->param, "%.*s", (int)(eq - dot - 1), dot + 1);
    if (!(s->t = technique_find(tech))) {
        log_error("--sweep: unknown technique '%s'", tech);
        return -1;
    }
    if (!technique_in(o->techniques, o->technique_count, s->t)) {
        log_error("--sweep: %s is not among the techniques selected with --technique", tech);
        return -1;
    }
    for (int i = 0; i < done_count; i++)
        if (done[i].t == s->t && strcmp(done[i].param, s->param) == 0) {
            log_error("--sweep: %s.%s is swept twice", tech, s->param);
            return -1;
        }

    /* Each value must be one that --set takes; spelled as the outputs do. */
    void *scratch = params_defaults(s->t);
    char *list = xstrdup(eq + 1), *rest = list;
    int rc = 0;
    for (char *v = strsep(&rest, ","); v && !rc; v = strsep(&rest, ",")) {
        char text[64];
        if (!*v) {
            log_error("--sweep: '%s' has an empty value", arg);
            rc = -1;
            break;
        }
        if ((rc = params_set(s->t, scratch, s->param, v)) != 0)
            break;
        params_value_text(s->t, scratch, s->param, text, sizeof text);
        for (int i = 0; i < s->count && !rc; i++)
            if (strcmp(s->values[i], text) == 0) {
                log_error("--sweep: %s.%s: %s is listed twice", tech, s->param, v);
                rc = -1;
            }
        s->values = xrealloc(s->values, sizeof *s->values * (size_t)(s->count + 1));
        s->values[s->count++] = xstrdup(text);
    }
    free(list);
    free(scratch);
    return rc;
}

/* Appends the configurations of technique t (index ti in technique_list):
 * the product of its sweeps over its base settings. */
static int add_configs(struct config_set *out, const struct config_desc *o, int ti, const struct sweep *sweeps,
                       int sweep_count)
{
    const struct technique *t = technique_list[ti];
    const struct sweep *mine[CONFIG_MAX_SWEEPS];
    int n = 0, total = 1;
    for (int i = 0; i < sweep_count && total <= CONFIG_MAX; i++)
        if (sweeps[i].t == t) {
            mine[n++] = &sweeps[i];
            total *= sweeps[i].count;  /* count <= one value per character of argv */
        }
    if (total > CONFIG_MAX - out->count) {
        log_error("--sweep: more than %d technique configurations in one run", CONFIG_MAX);
        return -1;
    }
    for (int k = 0; k < total; k++) {
        struct run_config *c = &out->configs[out->count++];
        c->technique = t;
        c->settings = memcpy(xmalloc(t->settings_size), o->settings[ti], t->settings_size);
        struct strbuf label = {0};
        strbuf_printf(&label, "%s", t->name);
        for (int i = 0, rest = k; i < n; rest /= mine[i]->count, i++) {
            const char *v = mine[i]->values[rest % mine[i]->count];
            params_set(t, c->settings, mine[i]->param, v);  /* checked by parse_sweep */
            strbuf_printf(&label, "%c%s=%s", i ? ',' : '@', mine[i]->param, v);
        }
        c->label = label.data;
        if (params_check(t, c->settings) != 0)
            return -1;
    }
    return 0;
}

/* Appends t's tuned cell, <t>@tuned, from o->tuned_dir. A technique with no
 * tuned file is listed in out->untuned with --settings both or auto (which
 * then runs its default cell), an error with tuned. */
static int add_tuned(struct config_set *out, const struct config_desc *o, const struct technique *t)
{
    struct tuned *tu = xcalloc(1, sizeof *tu);
    const int rc = tuned_load(o->tuned_dir, t, tu);
    if (rc != 0) {
        free(tu);
        if (rc == TUNED_NONE && o->mode == CONFIG_TUNED)
            log_error("%s/%s.json: no tuned settings for %s (shadowbench tune --write-tuned makes them)",
                      o->tuned_dir, t->name, t->name);
        else if (rc == TUNED_NONE)  /* said once, when the run starts */
            strbuf_list_printf(&out->untuned, ", ", "%s", t->name);
        return rc < 0 || o->mode == CONFIG_TUNED ? -1 : 0;
    }
    if (out->count == CONFIG_MAX) {
        tuned_free(tu);
        free(tu);
        log_error("--sweep: more than %d technique configurations in one run", CONFIG_MAX);
        return -1;
    }
    struct run_config *c = &out->configs[out->count++];
    c->technique = t;
    c->settings = memcpy(xmalloc(t->settings_size), tu->settings, t->settings_size);
    c->label = util_printf("%s" TUNED_SUFFIX, t->name);
    c->tuned = tu;
    return 0;
}

/* Appends t's presets, <t>@<name>: its defaults and the preset's values. */
static int add_presets(struct config_set *out, const struct technique *t)
{
    for (const struct technique_preset *p = t->presets; p && p->name; p++) {
        if (out->count == CONFIG_MAX) {
            log_error("more than %d technique configurations in one run", CONFIG_MAX);
            return -1;
        }
        struct run_config *c = &out->configs[out->count++];
        c->technique = t;
        c->settings = params_defaults(t);
        c->label = util_printf("%s@%s", t->name, p->name);
        if (params_apply(t, c->settings, p->params, c->label) != 0 || params_check(t, c->settings) != 0)
            return -1;
    }
    return 0;
}

int configs_build(struct config_set *out, const struct config_desc *o)
{
    memset(out, 0, sizeof *out);
    struct config_desc d = *o;
    if (d.mode == CONFIG_AUTO && (o->sweep_count || o->set_count))
        d.mode = CONFIG_DEFAULT;  /* the cells they change */
    o = &d;
    if (o->mode == CONFIG_TUNED && (o->sweep_count || o->set_count)) {
        log_error("--settings tuned: --set and --sweep change default cells, and this run has none");
        return -1;
    }
    struct sweep sweeps[CONFIG_MAX_SWEEPS];
    int count = 0, rc = 0;
    for (int i = 0; i < o->sweep_count && !rc; i++)
        if ((rc = parse_sweep(o, o->sweeps[i], sweeps, count, &sweeps[count])) == 0)
            count++;
        else
            sweep_clear(&sweeps[count]);
    out->configs = xcalloc(CONFIG_MAX, sizeof *out->configs);
    for (int i = 0; i < o->technique_count && !rc; i++) {
        int ti = 0;
        while (technique_list[ti] != o->techniques[i])
            ti++;
        const int before = out->count;
        if (o->mode != CONFIG_TUNED && o->mode != CONFIG_AUTO)
            rc = add_configs(out, o, ti, sweeps, count);
        if (!rc && o->mode != CONFIG_DEFAULT)
            rc = add_tuned(out, o, o->techniques[i]);
        if (!rc && o->mode == CONFIG_AUTO && out->count == before)  /* no tuned file */
            rc = add_configs(out, o, ti, sweeps, count);
        if (!rc && (o->mode == CONFIG_AUTO || o->mode == CONFIG_BOTH))  /* the named settings */
            rc = add_presets(out, o->techniques[i]);
    }
    for (int i = 0; i < count; i++)
        sweep_clear(&sweeps[i]);
    bool any_tuned = false;
    for (int i = 0; i < out->count; i++)
        any_tuned |= out->configs[i].tuned != NULL;
    if (!rc && o->mode == CONFIG_BOTH && !any_tuned) {  /* half of what was asked for */
        log_error("--settings both: none of the techniques has tuned settings in %s (shadowbench tune "
                  "--write-tuned makes them)", o->tuned_dir);
        rc = -1;
    }
    return rc;
}

void configs_free(struct config_set *s)
{
    for (int i = 0; i < s->count; i++) {
        free(s->configs[i].settings);
        free(s->configs[i].label);
        if (s->configs[i].tuned)
            tuned_free(s->configs[i].tuned);
        free(s->configs[i].tuned);
    }
    free(s->configs);
    strbuf_free(&s->untuned);
    memset(s, 0, sizeof *s);
}

const void *config_settings(const struct run_config *c, const struct scene *s)
{
    return c->tuned ? tuned_settings(c->tuned, s) : c->settings;
}
