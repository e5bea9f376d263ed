#!/usr/bin/env bash
# Runs cargo mutants on one part of the physics scope, testing each mutant
# with only the test targets that exercise that part (docs/testing.md,
# "Mutation testing"). Run it in a scratch clone: it mutates in place.
#
#   tools/mutants.sh PART OUTPUT_DIR [more cargo-mutants options]
#
# PART: direct | light | majorant | estimator | sampling | integrator | medium
set -euo pipefail
part=${1:?part}
out=${2:?output dir}
shift 2

render=(--test closed_form_render --test sphere_light --test surfaces
    --test analytic_scattering --test analytic_emission --test equiangular_mis
    --test equiangular_scale --test media_furnace)
case $part in
direct)
    files=(-f src/integrator/direct.rs)
    tests=("${render[@]}") ;;
estimator)
    files=(-f src/integrator/mod.rs)
    tests=("${render[@]}" --test envmap --test materials --test motion_blur
        --test motion_box --test aovs --test shutter_time) ;;
light)
    files=(-f src/light.rs -f 'src/light/**')
    tests=(--lib "${render[@]}" --test envmap) ;;
majorant)
    files=(-f src/medium/majorant_grid.rs)
    tests=(--lib --test majorant_grid --test media_grid --test media_grid_render
        --test analytic_transmittance --test motion_box --test motion_blur) ;;
sampling)
    files=(-f 'src/sampling/**')
    tests=(--lib --test sampling_chi2 --test envmap --test materials
        --test closed_form_render --test analytic_scattering
        --test equiangular_mis --test equiangular_scale) ;;
integrator)
    files=(-f 'src/integrator/**' -e src/integrator/direct.rs -e src/integrator/mod.rs)
    tests=(--lib "${render[@]}" --test analytic_transmittance --test media_grid
        --test height_fog --test tracking_roulette --test aovs --test motion_box) ;;
medium)
    files=(-f 'src/medium/**' -e src/medium/majorant_grid.rs)
    tests=(--lib "${render[@]}" --test analytic_transmittance --test media_grid
        --test media_grid_render --test height_fog --test sampling_chi2
        --test motion_box --test motion_blur) ;;
*)
    echo "unknown part: $part" >&2
    exit 2 ;;
esac
# The targets go to every cargo invocation (--cargo-arg), not only after `--`:
# that way the build phase (`cargo test --no-run`) also builds only them.
cargo_args=()
for a in "${tests[@]}"; do
    cargo_args+=("--cargo-arg=$a")
done
exec nice -n 19 cargo mutants --in-place --output "$out" "${files[@]}" "${cargo_args[@]}" "$@"
