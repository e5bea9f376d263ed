#!/usr/bin/env bash
# Runs cargo mutants on one part of the physics scope, testing each mutant
# with nextest over only the test targets that exercise that part
# (docs/testing.md, "Mutation testing"). Run it in a scratch clone: it
# mutates in place.
#
#   tools/mutants.sh PART OUTPUT_DIR [more cargo-mutants options]
#
# PART: estimator | tracking | equiangular | aov | light | majorant |
#       medium | phase | fog | blackbody | sampling | statistics
set -euo pipefail
part=${1:?part}
out=${2:?output dir}
shift 2

# Render-level closed forms: what every part of the estimator must answer to.
render=(--test closed_form_render --test sphere_light --test surfaces
    --test analytic_scattering --test analytic_emission --test equiangular_mis
    --test equiangular_scale --test media_furnace)
# Transmittance and free-flight closed forms through every kind of medium.
media=(--test analytic_transmittance --test media_grid --test media_grid_render
    --test height_fog --test tracking_roulette --test exact_voxels
    --test interior_media --test vdb_vs_homogeneous_image --test motion_box
    --test motion_blur --test motion_keyframed_media)
# The nextest profile (.config/nextest.toml): slow tests of other parts left out.
export NEXTEST_PROFILE=mutants
case $part in
estimator)
    export NEXTEST_PROFILE=mutants-lights
    files=(-f src/integrator/mod.rs -f src/integrator/direct.rs)
    tests=(--lib "${render[@]}" --test envmap --test materials --test motion_blur
        --test motion_box --test motion_keyframes --test aovs --test shutter_time
        --test textures --test light_sampling_chi2 --test interior_media) ;;
tracking)
    files=(-f src/integrator/tracking.rs -f 'src/integrator/tracking/**')
    tests=(--lib "${render[@]}" "${media[@]}") ;;
equiangular)
    files=(-f src/integrator/equiangular.rs)
    tests=(--lib "${render[@]}") ;;
aov)
    files=(-f src/integrator/aov.rs)
    tests=(--lib --test aovs --test motion_keyframes) ;;
light)
    export NEXTEST_PROFILE=mutants-lights
    files=(-f src/light/mod.rs -f 'src/light/**')
    tests=(--lib "${render[@]}" --test envmap --test light_sampling_chi2
        --test textures --test motion_keyframes) ;;
majorant)
    files=(-f src/medium/majorant_grid.rs)
    tests=(--lib --test majorant_grid "${media[@]}") ;;
medium)
    files=(-f 'src/medium/**' -e src/medium/majorant_grid.rs -e src/medium/phase.rs
        -e 'src/medium/phase/**' -e src/medium/height_fog.rs -e src/medium/blackbody.rs)
    tests=(--lib "${render[@]}" "${media[@]}" --test sampling_chi2 --test majorant_grid) ;;
phase)
    files=(-f src/medium/phase.rs -f 'src/medium/phase/**')
    tests=(--lib --test sampling_chi2 "${render[@]}") ;;
fog)
    files=(-f src/medium/height_fog.rs)
    tests=(--lib --test height_fog --test airlight "${render[@]}") ;;
blackbody)
    files=(-f src/medium/blackbody.rs)
    # The temperature-grid renders against Planck's law live in media_grid_render.
    tests=(--lib --test analytic_emission --test media_grid_render) ;;
sampling)
    files=(-f 'src/sampling/**' -e src/sampling/chi2.rs -e 'src/sampling/chi2/**'
        -e src/sampling/quadrature.rs)
    tests=(--lib --test sampling_chi2 --test envmap --test materials
        --test light_sampling_chi2 "${render[@]}") ;;
statistics)
    # The chi-square and quadrature helpers the tests themselves rely on.
    files=(-f src/sampling/chi2.rs -f 'src/sampling/chi2/**' -f src/sampling/quadrature.rs)
    tests=(--lib --test sampling_chi2 --test stats_helper --test envmap --test materials
        --test light_sampling_chi2 "${render[@]}") ;;
*)
    echo "unknown part: $part" >&2
    exit 2 ;;
esac
# The targets go to every cargo invocation (--cargo-arg), not only after `--`:
# that way the build phase also builds only them, and nextest runs only them.
cargo_args=()
for a in "${tests[@]}"; do
    cargo_args+=("--cargo-arg=$a")
done
# nextest runs each test in its own process, both cores busy, and stops at
# the first failure: a caught mutant costs its build and one failing test.
exec nice -n 19 cargo mutants --in-place --test-tool=nextest --timeout 120 \
    --output "$out" "${files[@]}" "${cargo_args[@]}" "$@"
