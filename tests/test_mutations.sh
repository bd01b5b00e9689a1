#!/bin/sh
# Protects the regression check's reach: each one-line mistake below, made
# in a copy of the shaders, makes `shadowbench check` on the committed
# baselines exit 1 with a REGRESSED (or IDLE) line naming the technique; the
# unchanged copy passes. The first five passed every test before the check
# existed (docs/regression.md).
# Usage: test_mutations.sh <shadowbench> <source root> <ground-truth cache>
set -u
sb=$1 root=$2 cache=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0

# mutate TECHNIQUE FILE SED-EXPRESSION WHAT
mutate() {
    technique=$1 file=$2 expression=$3 what=$4
    rm -rf "$tmp/shaders" && cp -r "$root/shaders" "$tmp/shaders"
    if [ -n "$file" ]; then
        sed -i -e "$expression" "$tmp/shaders/$file"
        if cmp -s "$root/shaders/$file" "$tmp/shaders/$file"; then
            echo "FAILED: the mutation '$what' changed nothing in $file (the shader moved on?)"
            failed=$((failed + 1))
            return
        fi
    fi
    out=$("$sb" check -q --technique "$technique" --shaders "$tmp/shaders" --baselines "$root/results/baselines" \
              --tuned "$root/results/tuned" \
                --cache "$cache" --out "$tmp/out" 2>&1)
    rc=$?
    if [ -z "$file" ]; then
        [ $rc = 0 ] && echo "ok: unchanged shaders pass ($technique)" ||
            { echo "FAILED: unchanged shaders: exit $rc"; printf '%s\n' "$out" | grep -v "^  pass"; failed=$((failed + 1)); }
        return
    fi
    if [ $rc = 1 ] && printf '%s\n' "$out" | grep -Eq "^  (REGRESSED|IDLE) .* $technique"; then
        echo "ok: $what -> exit 1, $(printf '%s\n' "$out" | grep -Ec "^  (REGRESSED|IDLE)") cell(s) of $technique"
    else
        echo "FAILED: $what -> exit $rc, not caught:"
        printf '%s\n' "$out" | grep -v "^  pass" | sed 's/^/    /'
        failed=$((failed + 1))
    fi
}

mutate pcf "" "" "none"
# The five of the issue.
mutate savsm savsm.glsl 's/0\.5 \* SAVSM_BOX_WIDTH_TEXELS/0.5 * 5.0/' "savsm ignores box_width_texels"
mutate pcf pcf.glsl 's/PCF_RADIUS_TEXELS \*/2.0 */' "pcf ignores radius_texels"
mutate pcss pcss.glsl 's/const bool square = SM_RECT_LIGHT;/const bool square = true;/' "pcss: square taps for disk lights"
mutate pcf shadow_taps.glsl 's/ + 0\.5 \* dot(abs(g), sm\.texel_size_uv);/;/' "receiver-plane bias without its half texel"
mutate pcss_savsm pcss_geometry.glsl 's/h \*= 0\.88622693;/;/' "pcss_savsm loses the disk factor"
# Others.
mutate hard hard.glsl 's/HARD_SLOPE_BIAS \* s\.texel_depth_slope/0.0/' "hard ignores slope_bias"
mutate vsm chebyshev.glsl 's/var \/ (var + dt \* dt)/var \/ (var + dt)/' "Chebyshev bound with dt, not dt squared"
mutate savsm savsm.glsl 's/reduce_light_bleeding(p, SAVSM_BLEED_REDUCTION)/p/' "savsm ignores bleed_reduction"
mutate pcss_savsm pcss_savsm.glsl 's/< PCSS_SAVSM_MIN_BLOCKER_FRACTION/< 0.001/' "pcss_savsm ignores min_blocker_fraction"
mutate pcss pcss_geometry.glsl 's/return 0\.5 \* light_scale/return 0.4 * light_scale/' "PCSS penumbra 20 % narrow"
mutate vsm chebyshev.glsl 's/if (t <= mean)/if (t < mean - 0.001)/' "Chebyshev's lit test 0.001 late"

[ "$failed" = 0 ] && echo "all caught" || echo "$failed not caught"
[ "$failed" = 0 ]
