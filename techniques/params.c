#include "params.h"
#include "base/log.h"

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MEMBER(settings, p, type) ((type *)((char *)(settings) + (p)->offset))
#define CMEMBER(settings, p, type) ((const type *)((const char *)(settings) + (p)->offset))

/* The choices of a PARAM_TAPS parameter, from TAP_COUNTS. */
static const char *const tap_count_names[] = {
#define X(n) #n,
    TAP_COUNTS(X)
#undef X
    NULL,
};

const double TUNE_CHOICES[] = {NAN};

const int tap_counts[TAP_COUNT_KINDS] = {
#define X(n) n,
    TAP_COUNTS(X)
#undef X
};

static bool is_tap_count(double v)
{
    for (int i = 0; i < TAP_COUNT_KINDS; i++)
        if (tap_counts[i] == v)
            return true;
    return false;
}

/* The values a parameter must be one of (its choices), or NULL for a range. */
static const char *const *choices(const struct technique_param *p)
{
    return p->type == PARAM_TAPS ? tap_count_names : p->type == PARAM_ENUM ? p->choices : NULL;
}

/* Logs "<technique>.<name>: <shown> is not one of: a, b, c"; returns -1. */
static int not_one_of(const struct technique *t, const struct technique_param *p, const char *shown)
{
    struct strbuf known = {0};
    strbuf_join(&known, choices(p), ", ");
    log_error("%s.%s: %s is not one of: %s", t->name, p->name, shown, known.data);
    strbuf_free(&known);
    return -1;
}

const struct technique_param *params_find(const struct technique *t, const char *name)
{
    for (const struct technique_param *p = t->params; p->name; p++)
        if (strcmp(p->name, name) == 0)
            return p;
    return NULL;
}

static double get(const struct technique_param *p, const void *settings)
{
    return p->type == PARAM_FLOAT ? *CMEMBER(settings, p, float) : *CMEMBER(settings, p, int);
}

static void put(const struct technique_param *p, void *settings, double v)
{
    if (p->type == PARAM_FLOAT)
        *MEMBER(settings, p, float) = (float)v;
    else
        *MEMBER(settings, p, int) = (int)v;
}

void params_put(const struct technique_param *p, void *settings, double v) { put(p, settings, v); }

double params_get(const struct technique_param *p, const void *settings) { return get(p, settings); }

int params_tune_values(const struct technique_param *p, double *values, int max)
{
    int n = 0;
    if (p->tune == TUNE_CHOICES) {
        const int count = p->type == PARAM_BOOL ? 2 : p->type == PARAM_TAPS ? TAP_COUNT_KINDS : 0;
        for (int i = 0; n < max && (p->type == PARAM_ENUM ? p->choices[i] != NULL : i < count); i++)
            values[n++] = p->type == PARAM_TAPS ? tap_counts[i] : i;
    } else {
        for (int i = 0; p->tune && !isnan(p->tune[i]) && n < max; i++)
            values[n++] = p->tune[i];
    }
    return n;
}

void *params_defaults(const struct technique *t)
{
    void *s = xcalloc(1, t->settings_size);
    for (const struct technique_param *p = t->params; p->name; p++)
        put(p, s, p->def);
    return s;
}

/* A float's text always has a '.' or an exponent, so GLSL reads a float. */
static void format_value(const struct technique_param *p, double v, char *buf, size_t n)
{
    switch (p->type) {
    case PARAM_FLOAT:
        snprintf(buf, n, "%.7g", v);  /* a float's digits: 0.0005, not 0.000500000024 */
        if (!strpbrk(buf, ".eEn"))
            strncat(buf, ".0", n - strlen(buf) - 1);
        break;
    case PARAM_BOOL: snprintf(buf, n, "%s", v != 0 ? "true" : "false"); break;
    case PARAM_ENUM: snprintf(buf, n, "%s", p->choices[(int)v]); break;
    case PARAM_INT:
    case PARAM_TAPS: snprintf(buf, n, "%d", (int)v); break;
    }
}

int params_set(const struct technique *t, void *settings, const char *name, const char *value)
{
    const struct technique_param *p = params_find(t, name);
    if (!p) {
        struct strbuf known = {0};
        for (const struct technique_param *q = t->params; q->name; q++)
            strbuf_list_printf(&known, ", ", "%s", q->name);
        log_error("%s.%s: unknown parameter (%s has: %s)", t->name, name, t->name,
                  known.data ? known.data : "none");
        strbuf_free(&known);
        return -1;
    }
    double v = 0;
    char *end = NULL;
    switch (p->type) {
    case PARAM_FLOAT:
        errno = 0;
        v = strtod(value, &end);
        /* Decimal only: strtod also takes " 1", "0x1p1", "inf". */
        const bool underflow = errno == ERANGE && fabs(v) < 1;  /* 1e-400: strtod gives 0 or a denormal */
        if (!*value || *end || (errno && !underflow) || !isfinite(v) || strpbrk(value, "xXpP \t") ||
            !strchr("+-.0123456789", value[0])) {
            log_error("%s.%s: '%s' is not a number", t->name, name, value);
            return -1;
        }
        if (underflow || (v != 0 && (float)fabs(v) < FLT_MIN)) {  /* 0, or digits lost, as a float */
            if (p->min <= 0 && p->max >= 0) {
                log_error("%s.%s: %s is too close to 0 for a float (write 0)", t->name, name, value);
                return -1;
            }
            v = 0;  /* 0 is below the range: the range check says so */
        }
        v += 0.0;  /* -0 is 0: one spelling in the outputs, and one cell in a sweep */
        break;
    case PARAM_INT:
    case PARAM_TAPS:
        errno = 0;
        v = (double)strtol(value, &end, 10);
        if (!*value || *end || errno) {
            log_error("%s.%s: '%s' is not a whole number", t->name, name, value);
            return -1;
        }
        if (p->type == PARAM_TAPS && !is_tap_count(v))
            return not_one_of(t, p, value);
        break;
    case PARAM_BOOL:
        if (!strcasecmp(value, "true") || !strcmp(value, "1") || !strcasecmp(value, "on"))
            v = 1;
        else if (!strcasecmp(value, "false") || !strcmp(value, "0") || !strcasecmp(value, "off"))
            v = 0;
        else {
            log_error("%s.%s: '%s' is not true or false", t->name, name, value);
            return -1;
        }
        break;
    case PARAM_ENUM: {
        int i = 0;
        while (p->choices[i] && strcmp(p->choices[i], value) != 0)
            i++;
        if (!p->choices[i]) {
            char *quoted = util_printf("'%s'", value);
            not_one_of(t, p, quoted);
            free(quoted);
            return -1;
        }
        v = i;
        break;
    }
    }
    if ((p->type == PARAM_FLOAT || p->type == PARAM_INT) && (v < p->min || v > p->max)) {
        char lo[64], hi[64];
        format_value(p, p->min, lo, sizeof lo);
        format_value(p, p->max, hi, sizeof hi);
        log_error("%s.%s: %s is out of range [%s, %s]", t->name, name, value, lo, hi);
        return -1;
    }
    put(p, settings, v);
    return 0;
}

int params_apply(const struct technique *t, void *settings, const char *list, const char *label)
{
    char *copy = xstrdup(list), *rest = copy, *names[64];
    int rc = 0, given = 0;
    for (char *item = strsep(&rest, ","); item && !rc; item = strsep(&rest, ",")) {
        char *eq = strchr(item, '=');
        if (!eq) {
            log_error("cell '%s': '%s' is not parameter=value", label, item);
            rc = -1;
            break;
        }
        *eq = '\0';
        /* Each parameter once: "p=1,p=2" would be two cells in one name. */
        for (int i = 0; i < given && !rc; i++)
            if (strcmp(names[i], item) == 0) {
                log_error("cell '%s': %s is given twice", label, item);
                rc = -1;
            }
        if (given < (int)(sizeof names / sizeof *names))
            names[given++] = item;
        if (!rc)
            rc = params_set(t, settings, item, eq + 1);
    }
    free(copy);
    return rc;
}

int params_taps(const struct technique *t, const void *settings, int *taps, int max)
{
    int n = 0;
    for (const struct technique_param *p = t->params; p->name; p++)
        if (p->type == PARAM_TAPS) {
            if (n < max)
                taps[n] = (int)get(p, settings);
            n++;
        }
    return n;
}

int params_check(const struct technique *t, const void *settings)
{
    char why[256];
    if (!t->check || t->check(settings, why, sizeof why) == 0)
        return 0;
    log_error("%s: %s", t->name, why);
    return -1;
}

static void upper(char *dst, const char *src, size_t n)
{
    size_t i = 0;
    for (; src[i] && i + 1 < n; i++)
        dst[i] = (char)toupper((unsigned char)src[i]);
    dst[i] = '\0';
}

int params_grid_taps(const char *name, int taps, char *why, size_t why_size)
{
    int side = 1;
    while (side * side < taps)
        side++;
    if (side * side == taps)
        return 0;
    struct strbuf squares = {0};
    for (int i = 0; i < TAP_COUNT_KINDS; i++) {
        for (side = 1; side * side < tap_counts[i]; side++)
            ;
        if (side * side == tap_counts[i])
            strbuf_list_printf(&squares, ", ", "%d", tap_counts[i]);
    }
    snprintf(why, why_size, "pattern=grid needs a square %s (%s), not %d", name, squares.data, taps);
    strbuf_free(&squares);
    return -1;
}

void params_defines(const struct technique *t, const void *settings, struct strbuf *out)
{
    char tech[64], name[64], choice[64];
    upper(tech, t->name, sizeof tech);
    for (const struct technique_param *p = t->params; p->name; p++) {
        upper(name, p->name, sizeof name);
        double v = get(p, settings);
        if (p->type == PARAM_FLOAT) {
            char buf[64];
            format_value(p, v, buf, sizeof buf);
            strbuf_printf(out, "#define %s_%s %s\n", tech, name, buf);
        } else {
            strbuf_printf(out, "#define %s_%s %d\n", tech, name, (int)v);
        }
        for (int k = 0; p->type == PARAM_ENUM && p->choices[k]; k++) {
            upper(choice, p->choices[k], sizeof choice);
            strbuf_printf(out, "#define %s_%s_%s %d\n", tech, name, choice, k);
        }
    }
}

cJSON *params_json(const struct technique *t, const void *settings)
{
    cJSON *o = cJSON_CreateObject();
    for (const struct technique_param *p = t->params; p->name; p++) {
        double v = get(p, settings);
        switch (p->type) {
        case PARAM_FLOAT: {
            char buf[64];  /* the float's shortest decimal, as `list` prints it */
            format_value(p, v, buf, sizeof buf);
            cJSON_AddNumberToObject(o, p->name, strtod(buf, NULL));
            break;
        }
        case PARAM_INT:
        case PARAM_TAPS: cJSON_AddNumberToObject(o, p->name, v); break;
        case PARAM_BOOL: cJSON_AddBoolToObject(o, p->name, v != 0); break;
        case PARAM_ENUM: cJSON_AddStringToObject(o, p->name, p->choices[(int)v]); break;
        }
    }
    return o;
}

void *params_from_json(const struct technique *t, const cJSON *o)
{
    if (!cJSON_IsObject(o)) {
        log_error("%s: the parameters are not an object", t->name);
        return NULL;
    }
    void *s = params_defaults(t);
    const cJSON *item;
    cJSON_ArrayForEach(item, o) {
        char text[64];
        if (cJSON_IsBool(item))
            snprintf(text, sizeof text, "%s", cJSON_IsTrue(item) ? "true" : "false");
        else if (cJSON_IsNumber(item) && isfinite(item->valuedouble))
            snprintf(text, sizeof text, "%.17g", item->valuedouble);
        else if (cJSON_IsString(item) && strlen(item->valuestring) < sizeof text)
            snprintf(text, sizeof text, "%s", item->valuestring);
        else {
            log_error("%s.%s: not a number, true/false or a name", t->name, item->string);
            goto fail;
        }
        if (params_set(t, s, item->string, text) != 0)  /* unknown (renamed, removed) or out of range */
            goto fail;
    }
    for (const struct technique_param *p = t->params; p->name; p++)
        if (!cJSON_GetObjectItemCaseSensitive(o, p->name)) {
            log_error("lacks %s.%s (recorded before the parameter existed)", t->name, p->name);
            goto fail;
        }
    if (params_check(t, s) == 0)
        return s;
fail:
    free(s);
    return NULL;
}

int params_value_text(const struct technique *t, const void *settings, const char *name, char *buf,
                      size_t size)
{
    const struct technique_param *p = params_find(t, name);
    if (!p)
        return -1;
    format_value(p, get(p, settings), buf, size);
    return 0;
}

void params_summary(const struct technique *t, const void *settings, struct strbuf *out)
{
    for (const struct technique_param *p = t->params; p->name; p++) {
        char buf[64];
        format_value(p, get(p, settings), buf, sizeof buf);
        strbuf_list_printf(out, " ", "%s=%s", p->name, buf);
    }
}

void params_print(const struct technique *t, FILE *f)
{
    static const char *const type_name[] = {
        [PARAM_FLOAT] = "float", [PARAM_INT] = "int", [PARAM_BOOL] = "bool",
        [PARAM_ENUM] = "enum", [PARAM_TAPS] = "int",
    };
    for (const struct technique_param *p = t->params; p->name; p++) {
        char def[64], lo[64], hi[64];
        format_value(p, p->def, def, sizeof def);
        if (choices(p)) {
            struct strbuf c = {0};
            strbuf_join(&c, choices(p), "|");
            fprintf(f, "    %-16s %-5s default %-10s one of %s\n", p->name, type_name[p->type], def,
                    c.data);
            strbuf_free(&c);
        } else {
            bool boolean = p->type == PARAM_BOOL;  /* false and true */
            format_value(p, boolean ? 0 : p->min, lo, sizeof lo);
            format_value(p, boolean ? 1 : p->max, hi, sizeof hi);
            fprintf(f, "    %-16s %-5s default %-10s range [%s, %s]\n", p->name,
                    type_name[p->type], def, lo, hi);
        }
        fprintf(f, "        %s\n", p->help);
    }
}
