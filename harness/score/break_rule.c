#include "break_rule.h"
#include "base/util.h"

const char break_rule_text[] =
    "a value breaks a technique where its V has any NaN/Inf, or, against the reference value, its rmse is "
    "at least " UTIL_STR(BREAK_RULE_RMSE_FACTOR) " times as large and " UTIL_STR(BREAK_RULE_RMSE_RISE)
    " larger, or its leak_fraction or dark_fraction " UTIL_STR(BREAK_RULE_FRACTION_RISE) " larger";

bool break_rule_broken(const struct metrics *m, const struct metrics *ref)
{
    if (m->nonfinite > 0)
        return true;
    if (!metrics_scored(m) || !metrics_scored(ref))
        return false;
    return (m->rmse >= BREAK_RULE_RMSE_FACTOR * ref->rmse && m->rmse >= ref->rmse + BREAK_RULE_RMSE_RISE) ||
           m->leak_fraction >= ref->leak_fraction + BREAK_RULE_FRACTION_RISE ||
           m->dark_fraction >= ref->dark_fraction + BREAK_RULE_FRACTION_RISE;
}

void break_rule_points(const struct metrics *const *m, int n, int ref, int *below, int *above)
{
    *below = *above = -1;
    if (ref < 0 || ref >= n || !m[ref])
        return;
    for (int k = ref - 1; k >= 0 && *below < 0; k--)
        if (m[k] && break_rule_broken(m[k], m[ref]))
            *below = k;
    for (int k = ref + 1; k < n && *above < 0; k++)
        if (m[k] && break_rule_broken(m[k], m[ref]))
            *above = k;
}
