#!/bin/sh
# Protects the regression check's reach: each one-line mistake below, made
# in a copy of the shaders, makes `shadowbench check` on the committed
# baselines exit 1 with a REGRESSED (or IDLE) line naming the technique; the
# unchanged copy passes. The first five passed every test before the check
# existed (docs/regression.md). Each is checked on one scene where check
# over every scene catches it (most are caught on many: the receiver-plane
# bias's on 16 scenes, pcss's narrow penumbra on 19), which keeps the
# suite to its budget; the unchanged copy passes on those scenes.
# Usage: test_mutations.sh <shadowbench> <source root> <ground-truth cache>
set -u
sb=$1 root=$2 cache=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0

# mutate TECHNIQUE SCENES FILE SED-EXPRESSION WHAT (SCENES: comma-separated)
mutate() {
    technique=$1 scenes=$2 file=$3 expression=$4 what=$5
    rm -rf "$tmp/shaders" && cp -r "$root/shaders" "$tmp/shaders"
    if [ -n "$file" ]; then
        sed -i -e "$expression" "$tmp/shaders/$file"
        if cmp -s "$root/shaders/$file" "$tmp/shaders/$file"; then
            echo "FAILED: the mutation '$what' changed nothing in $file (the shader moved on?)"
            failed=$((failed + 1))
            return
        fi
    fi
    out=$("$sb" check -q --technique "$technique" $(printf -- '--scene %s ' $(echo "$scenes" | tr , ' ')) --shaders "$tmp/shaders" --baselines "$root/results/baselines" \
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

mutate pcf,savsm,pcss,pcss_savsm,hard,vsm parallel_planes,parallel_planes_disk,contact_hardening,overlapping_occluders \
    "" "" "none"
# The five of the issue.
mutate savsm parallel_planes savsm.glsl 's/0\.5 \* SAVSM_BOX_WIDTH_TEXELS/0.5 * 5.0/' "savsm ignores box_width_texels"
mutate pcf parallel_planes pcf.glsl 's/PCF_RADIUS_TEXELS \*/2.0 */' "pcf ignores radius_texels"
mutate pcss parallel_planes_disk pcss.glsl 's/const bool square = SM_RECT_LIGHT;/const bool square = true;/' "pcss: square taps for disk lights"
mutate pcf contact_hardening shadow_taps.glsl 's/ + 0\.5 \* dot(abs(g), sm\.texel_size_uv);/;/' "receiver-plane bias without its half texel"
mutate pcss_savsm parallel_planes_disk pcss_geometry.glsl 's/h \*= 0\.88622693;/;/' "pcss_savsm loses the disk factor"
# Others.
mutate hard contact_hardening hard.glsl 's/HARD_SLOPE_BIAS \* s\.texel_depth_slope/0.0/' "hard ignores slope_bias"
mutate vsm parallel_planes chebyshev.glsl 's/var \/ (var + dt \* dt)/var \/ (var + dt)/' "Chebyshev bound with dt, not dt squared"
mutate savsm overlapping_occluders savsm.glsl 's/reduce_light_bleeding(p, SAVSM_BLEED_REDUCTION)/p/' "savsm ignores bleed_reduction"
mutate pcss_savsm contact_hardening pcss_savsm.glsl 's/< PCSS_SAVSM_MIN_BLOCKER_FRACTION/< 0.001/' "pcss_savsm ignores min_blocker_fraction"
mutate pcss parallel_planes pcss_geometry.glsl 's/return 0\.5 \* light_scale/return 0.4 * light_scale/' "PCSS penumbra 20 % narrow"
mutate vsm parallel_planes chebyshev.glsl 's/if (t <= mean)/if (t < mean - 0.001)/' "Chebyshev's lit test 0.001 late"

[ "$failed" = 0 ] && echo "all caught" || echo "$failed not caught"
[ "$failed" = 0 ]
