#!/usr/bin/env bash
# scripts/results: the stamped page from a small fake out/ directory (JSON files with the keys
# the main job writes), the numbers in its tables, and "not run" for a missing input.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
results=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir -p "$dir/out/figures"
cat >"$dir/out/verify-matrices.json" <<'JSON'
{"systems": 1234, "failures": 0, "tolerance": 1e-9, "worst_relative_error": 3.25e-12,
 "worst_system": "refract sphere fake", "all": {"tir_checked": 56},
 "families": {"sphere": {"systems": 1000, "failures": 0, "worst_relative_error": 3.25e-12,
                         "printed": {"failures": 777}}}}
JSON
cat >"$dir/out/verify-bounds.json" <<'JSON'
{"systems": 2001, "skipped": 99, "pass": true,
 "corrected": {"A": {"failures": 0, "min": 1.0, "max": 12.5}},
 "printed": {"D": {"failures": 4321, "min": -15.5}},
 "tensor_crosscheck": {"worst": 2.5e-11, "tolerance": 1e-7},
 "fit": {"systems": 1999, "worst_attained_deviation": 2.75e-5, "tolerance": 0.02},
 "onset": {"pinhole_systems": 208, "found_corrected": 135, "smallest_corrected": 0.00033}}
JSON
cat >"$dir/out/verify-stability.json" <<'JSON'
{"samples": 1000, "seed": 7, "threads": 2, "seconds": 12.0, "accuracy": 1e-8, "failures": 0,
 "all": {"total": 1000, "checked": 600, "worst_error": 1.5e-9, "sampled": 3,
         "refused": {"tir": 300, "grazing": 50, "illcond": 40, "overflow": 10},
         "invariant_failures": 0, "beyond_own_bound": 0, "wrong_refusals": 0,
         "matrices_at_tir": 0, "silent_nonfinite": 0, "sampled_failures": 0,
         "worst_error_over_bound": 0.25, "largest_bound": 9.9e-9, "sampled_unresolved": 1},
 "regimes": {"grazing": {"total": 100, "checked": 90, "refused": {"grazing": 10},
                         "worst_error": 1e-15, "sampled": 1}}}
JSON
cat >"$dir/out/verify-illuminance.json" <<'JSON'
{"cases": 900, "failures": 0, "tolerance": 1e-9, "condition_away": 1e3,
 "point": {"cases": 300, "failures": 0, "compared": 290, "refused_caustic": 10,
           "worst_formula_error": 7e-11, "worst_relative_error_away": 4.2e-10,
           "worst_error_over_condition_bound_near": 0.5, "largest_condition_answered": 6300},
 "all": {"cases": 900, "failures": 0, "compared": 850, "refused_caustic": 50,
         "worst_formula_error": 2e-10, "worst_relative_error_away": 4.2e-10,
         "worst_error_over_condition_bound_near": 3.25, "largest_condition_answered": 2.2e7},
 "pool": {"h_air": 2, "h_water": 1, "n_water": 1.333, "cone_deg": 40,
          "flux_ratio_eq8": 0.9999999999999, "flux_ratio_printed_eq1": 0.750188}}
JSON
cat >"$dir/out/bench-illuminance.json" <<'JSON'
{"grid": 128, "reference_rays": 1000000, "targets_met": true,
 "cases": [{"case": "ball, parallel", "method": "grid-pencil", "rays": 1274139, "seconds": 0.906,
            "worst_relative_error_smooth": 0.00446, "rms_error": 0.0005, "flux_relative_error": 6.3e-8}],
 "fig11": {"grid_pencil": {"rays": 4122087, "seconds": 47.0, "rms": 0.00189, "dim_rms": 0.0241},
           "polygons": {"rays": 20826629, "seconds": 34.1, "rms": 0.00359, "dim_rms": 0.0557},
           "photons": [{"rays": 1664100, "seconds": 2.9, "rms": 0.188, "dim_rms": 0.70}],
           "equal_error": {"rays": 3.8e9, "seconds": 2310, "measured": false, "speedup": 49}}}
JSON
cat >"$dir/out/fig10-1989.log" <<'LOG'
effects plan for scenes/glass.json:
  caustics       on: 1 light(s) through 'glass' onto 'table', 1 map(s)
pencil-traced 1024x682 at 9 spp in 250.000 s (rho 0.5, bounds corrected): samples 1.4% matrix
ray interpolation: 696435 lattice points
caustics: 1 map(s) of 512 cells along the longer side by grid-pencil (grids of 448 x 448 rays), 0 empty; 1404238 light rays in 10.4 s (part of the render time); 3.2% of the mapped light fell beside the maps
LOG
mkdir -p "$dir/out/area"
cat >"$dir/out/area/area.json" <<'JSON'
{"cases": [{"case": "ball", "grid": 64, "reference": {"mesh": 64, "rays_per_side": 65, "rays": 193773748,
  "seconds": 145.6, "own_rms": 2.3e-05, "half_mesh": 32, "exact_rms": null, "exact_max": null},
  "rows": [{"case": "ball", "mesh": 2, "filter": "quadratic", "rays": 17598702, "seconds": 9.437,
            "rms": 8.38e-04, "p99": 3.1e-03, "max": 3.74e-03, "flux_relative_error": -1.46e-03,
            "filtered": 166532, "resampled": 402138}]}],
 "size_sweep": [{"scale": 0.5, "cell_rad": 0.0182, "mesh": 2, "plain": {"rms": 0.0239, "max": 0.1, "seconds": 1.0},
                 "quadratic": {"rms": 0.0214, "max": 0.1, "seconds": 6.0},
                 "linear": {"rms": 0.0224, "max": 0.1, "seconds": 5.2}}],
 "reference_mesh": 64, "reference_rays_per_side": 65, "quick": false}
JSON
mkdir -p "$dir/out/caustics"
cat >"$dir/out/caustics/caustics.json" <<'JSON'
{"runs": 3, "quick": false,
 "cases": [{"case": "fig11", "scene": "fig11-caustics.json", "width": 512, "height": 512, "spp": 1,
            "reference_rms_estimate": 0.00378, "pencil_over_exact": 2.009,
            "equal_error": {"photon_rays": 8.9e7, "photon_seconds": 28.6, "over_grid_pencil": 9.75,
                            "grid_pencil_seconds": 2.93},
            "variants": [{"variant": "reference", "caustic_method": "photons", "map_rays": 67125249,
                          "seconds": 17.8, "against": null, "rms": null, "p99": null, "max": null},
                         {"variant": "pencil", "caustic_method": "grid-pencil", "map_rays": 1403172,
                          "seconds": 3.256, "against": "reference", "rms": 0.005166,
                          "p99": 0.02099, "max": 0.2999}]}]}
JSON
mkdir -p "$dir/out/beam"
cat >"$dir/out/beam/beam.json" <<'JSON'
{"benchmark": "beam", "size": 256, "reference_spp": 256, "rho": 0.5, "runs": 3, "quick": false,
 "cases": [{"case": "fig11", "what": "torus", "faces": 100, "width": 256, "height": 256,
            "variants": [{"variant": "reference", "renderer": "exact", "spp": 256, "seconds": 16.0,
                          "mean": null, "p99": null, "max": null},
                         {"variant": "beam", "renderer": "beam", "spp": 1, "seconds": 1.223,
                          "mean": 4.972e-04, "p99": 1.439e-02, "max": 2.093e-01},
                         {"variant": "beam-probe", "renderer": "beam", "spp": 1, "seconds": 0.912,
                          "mean": 5.199e-04, "p99": 1.5e-02, "max": 1.8e-01},
                         {"variant": "exact-16", "renderer": "exact", "spp": 16, "seconds": 1.056,
                          "mean": 8.398e-04, "p99": 2.1e-02, "max": 9.9e-02}],
            "equal_error": {"exact_seconds": 1.981, "bracket": "inside", "exact_over_beam": 1.62,
                            "exact_seconds_probe": 1.9, "bracket_probe": "inside",
                            "exact_over_beam_probe": 2.1},
            "beam_over_exact16": 1.158, "beam_over_pencil16": 1.072,
            "fig10": {"default": {"samples": 65536, "within": 0.998215, "max": 0.1041,
                                  "mismatches": 117, "seconds_measured": 3.0},
                      "certified": {"samples": 65536, "within": 1, "max": 0.1041,
                                    "mismatches": 0, "seconds_measured": 4.0}}}]}
JSON
mkdir -p "$dir/out/star"
cat >"$dir/out/star/verify-star.json" <<'JSON'
{"verification": "star", "focal_mm": 50, "pass": true,
 "slopes": [{"n": 1.5, "phi_deg": 0, "relative_error_at_1e-4": 4.58e-09, "sign": "-N",
             "slope_at_1pct": 0.1482, "slope_at_10pct": 0.482, "tir_from_slope": null, "pass": true}],
 "profiles": [{"sigma1": 0.02, "sigma2": 0.1, "weight2": 0.5, "tv_distance": 3.528e-3,
               "rms_exact_mm": 1.8, "rms_linear_mm": 1.78, "rms_ratio": 1.01286, "lost_to_tir": 0}]}
JSON
cat >"$dir/out/star/bench-star.json" <<'JSON'
{"benchmark": "star", "runs": 5, "rows": [{"size": 512, "threads": 1, "seconds": 0.0412,
 "kernel_seconds": 0.0011, "kernel_side": 381}]}
JSON
cat >"$dir/out/verify-dispersion.json" <<'JSON'
{"verification": "dispersion", "cases": 5248, "compared": 5248, "refused": 0, "failures": 0,
 "worst_relative_error": 1.179e-11, "tolerance": 1e-9, "printed": {"failures": 4085, "worst_relative_error": 6.87},
 "linearity": [{"delta_lambda_nm": 10, "median": 2.465e-2, "p90": 0.1036, "max": 0.74, "cases": 4085,
                "optics_median": 5.526e-4, "optics_p90": 8.24e-2}]}
JSON
for t in geometric image; do
  cat >"$dir/out/bench-pencil-$t.json" <<JSON
{"benchmark": "pencil", "tolerance": "$t", "results": [{"spp": 49, "mode": "default",
 "exact_s": 1.25, "pencil_s": 0.25, "ratio": 0.2, "fraction_within": 0.999908,
 "max_error": 0.597, "image_rms": 0.01406, "image_max": 0.1261, "image_bias": 0.00031}]}
JSON
done
mkdir -p "$dir/out/curves"
cat >"$dir/out/curves/curves.json" <<'JSON'
{"benchmark": "curves", "runs": 3, "threads": 1, "instructions": "callgrind, one thread",
 "rows": [{"curve": "spheres", "x": 1000, "mode": "default", "exact_s": 4.027, "pencil_s": 4.195,
           "ratio": 1.042, "instruction_ratio": null},
          {"curve": "spheres", "x": 1000, "mode": "certified", "exact_s": 3.9, "pencil_s": 4.3,
           "ratio": 1.115, "instruction_ratio": null},
          {"curve": "rho", "x": 0.05, "mode": "default", "exact_s": 1.17, "pencil_s": 0.426,
           "ratio": 0.363, "instruction_ratio": 0.2428}]}
JSON
mkdir -p "$dir/out/dispersion"
cat >"$dir/out/dispersion/dispersion.json" <<'JSON'
{"benchmark": "dispersion", "scene": "scenes/fig14.json", "size": 256, "spp": 1,
 "reference_bins": 400, "runs": 3, "quick": false, "dispersive_pencil": "not built yet",
 "targets": {"time_over_pencil": 3.71, "time_over_pencil_target": 1.3, "time_met": false,
             "delta_e2000_mean": 0.1096, "delta_e2000_mean_target": 1.0, "delta_e_met": true,
             "time_over_exact_nd": 5.2, "faster_than_exact_nd": false},
 "methods": [{"method": "reference", "renderer": "exact", "wavelengths": "fan", "bins": 400,
              "seconds": 12.925, "over_exact_nd": 279.548, "rays": 79319783,
              "delta_e2000_mean": null, "delta_e2000_p99": null, "delta_e2000_max": null},
             {"method": "exact-takagi9", "renderer": "exact", "wavelengths": "primary", "bins": 9,
              "seconds": 0.319, "over_exact_nd": 6.890, "rays": 3117397,
              "delta_e2000_mean": 0.6919, "delta_e2000_p99": 13.3169, "delta_e2000_max": 43.8106}]}
JSON
for spp in 1 4; do # the equal-error runs: the same methods at two sample counts
  cat >"$dir/out/dispersion/equal-spp$spp.json" <<JSON
{"benchmark": "dispersion", "scene": "scenes/fig14.json", "size": 96, "spp": $spp,
 "reference_bins": 100, "reference_spp": 64, "runs": 3, "quick": false,
 "methods": [{"method": "reference", "seconds": 50.5, "delta_e2000_mean": null},
             {"method": "beam-solids", "seconds": 0.9$spp, "delta_e2000_mean": $spp.25}]}
JSON
done
cat >"$dir/out/figures/summary.json" <<'JSON'
{"scene": "built-in fig8", "width": 256, "height": 256, "threads": 1, "runs": 3,
 "time": "process CPU seconds, median of runs",
 "fig8": {"spp": 9, "speedup": 2.345},
 "fig9": [{"spp": 9, "ratio": 0.4321},
          {"spp": 49, "ratio": 0.1789, "exact_s": 1.2, "pencil_s": 0.21468, "povray_s": 5.0,
           "povray_rays": 19653840, "pencil_over_povray": 0.042936, "exact_over_povray": 0.24}],
 "fig9_below_0_1_from_spp": null,
 "fig10": {"rho": 0.5, "spp": 9, "samples": 589824, "fraction_within": 0.99987654,
           "max_error": 0.5584, "p99": 0.351, "mismatches": 0, "image_rms": 0.0207},
 "targets": {"spp": 49,
   "pencil": {"ratio": 0.1789, "errors": {"samples": 1000000, "fraction_within": 0.9999,
                                          "max_error": 0.5971}},
   "certified": {"ratio": 0.2075, "errors": {"samples": 1000000, "fraction_within": 1,
                                             "max_error": 0.3916}},
   "no_accuracy": {"rho": 100, "brightness_tol": 100, "ratio": 0.1244,
                   "certified_ratio": 0.1311}},
 "sweep": [{"rho": 0.05, "variant": "printed", "ratio": 1.0987,
            "errors": {"spp": 9, "fraction_within": 0.968, "p99": 0.07, "max_error": 1.9}}],
 "paper": {"fig8_speedup_9spp": 7.6, "fig9_ratio_49spp": 0.1, "fig10_fraction_within": 0.998,
           "fig10_max_error": 0.66}}
JSON
page=$dir/results.md
"$results" "$dir/out" -o "$page" >/dev/null 2>"$dir/err"; rc=$?
check "exit 0 with every input" "[ $rc -eq 0 ]"
check "stamped: commit" "grep -Eq '^- commit: ([0-9a-f]{7,}(-dirty)?|unknown)' '$page'"
check "stamped: UTC date" "grep -Eq '^- date: [0-9]{4}-[0-9]{2}-[0-9]{2} [0-9]{2}:[0-9]{2} UTC' '$page'"
check "stamped: cores" "grep -Eq '^- machine: [0-9]+ cores' '$page'"
check "matrices: systems and worst error" "grep -q '| 1234 | 56 | 0 | 3.25e-12 |' '$page'"
check "matrices: printed failures per family" "grep -q '| sphere | 1000 | 3.25e-12 | 0 | 777 |' '$page'"
check "bounds: systems" "grep -q '2001 systems verified, 99 skipped' '$page'"
check "bounds: corrected row" "grep -q '| A | 0 | 1 | 12.5 |' '$page'"
check "bounds: printed failures" "grep -q '| D | - | - | - | 4321 | -15.5 |' '$page'"
check "Fig. 8 speed-up against the paper's 7.6x" "grep -q '| 7.6x | 2.35x |' '$page'"
check "Fig. 9 ratio per spp" "grep -q 'at 49 spp | < 0.10 | 0.179 |' '$page'"
check "Fig. 10 within rho and largest error" \
  "grep -q '| 99.8% | 99.9877% |' '$page' && grep -q '| 0.66 | 0.558 |' '$page'"
check "targets, default and certified" \
  "grep -q '| default | 0.179 | 99.9900% | 100 | 0.597 | no |' '$page' && grep -q '| certified | 0.207 | 100.0000% | 0 | 0.392 | no |' '$page'"
check "no-accuracy ratio" "grep -q 'is 0.124 (certified 0.131)' '$page'"
check "rho sweep row" "grep -q '| 0.05 | printed | 1.099 | 96.8000% | 0.070 | 1.900 |' '$page'"
check "stability: the counts per regime" \
  "grep -q '| grazing | 100 | 90 | - | 10 | - | - | 1.00e-15 | 1 |' '$page' && grep -q '| all | 1000 | 600 | 300 | 50 | 40 | 10 | 1.50e-09 | 3 |' '$page'"
check "stability: failures and silent NaN/Inf" "grep -q 'silent NaN/Inf 0, sample 0' '$page'"
check "illuminance: a group's row" "grep -q '| point, sweep | 300 | 0 | 290 | 10 | 7.00e-11 | 4.20e-10 | 0.50 | 6.3e+03 |' '$page'"
check "illuminance: the pool's energy check" "grep -q '1.000000000000 by Eq. (8), 0.750188 by the printed' '$page'"
check "illuminance maps: a case's row and Fig. 11's speed-up" "grep -q '| ball, parallel | grid-pencil | 1274139 | 0.906 | 4.46e-03 |' '$page' && grep -q '49 times grid-pencil' '$page'"
check "illuminance maps: the polygons' row on Fig. 11" "grep -q '20826629 rays in 34.1 s, RMS 3.59e-03 (dim cells 5.57e-02)' '$page'"
check "fig10: the render's closing lines" \
  "grep -q '^    pencil-traced 1024x682 at 9 spp in 250.000 s' '$page' && grep -q '^    ray interpolation: 696435' '$page' && grep -q '^    caustics: 1 map(s) of 512 cells' '$page' && ! grep -q '^    effects plan' '$page' && ! grep -q '^    caustics       on' '$page'"
check "dispersion: Takagi's row" "grep -q '| exact-takagi9 | exact | primary | 9 | 0.319 | 6.89 | 3117397 | 0.692 | 13.317 | 43.811 |' '$page'"
check "dispersion: the targets' verdicts" "grep -q 'pencil-spectral 3.71 times pencil.s time (target <= 1.3; the paper: about 1.2): not met; its mean dE2000 0.110 (target <= 1): met; 5.20 times exact-nd.s time .*: not reproduced' '$page'"
check "nothing reported as not run" "! grep -q 'not run' '$page'"
check "dispersion at equal error: a column pair per spp, a row per method" "grep -q '| method | 1 spp dE | s | 4 spp dE | s |' '$page' && grep -q '| beam-solids | 1.25 | 0.910 | 4.25 | 0.940 |' '$page' && grep -q 'spectral fan with 100 bins at 64 spp' '$page'"
check "Fig. 9 beside POV-Ray: the 49-spp row" \
  "grep -q '| 49 | 1.200 | 0.215 | 5.000 | 0.179 | 0.043 | 0.240 |' '$page'"
check "image-space tolerance: a row per tolerance" \
  "grep -q '| geometric | default | 49 | 1.250 | 0.250 | 0.200 | 99.9908% | 0.597 | 0.0141 | 0.1261 | 0.00031 |' '$page' && grep -q '| image | default | 49 |' '$page'"
check "caustics: the pencil's row and the equal-error line" \
  "grep -q '| pencil | grid-pencil | 1403172 | 3.256 | 5.17e-03 | 2.10e-02 | 3.00e-01 | reference |' '$page' && grep -q 'with about 8.9e+07 rays in 28.6 s, 9.75 times' '$page'"
check "area: a row and the size sweep" \
  "grep -q '| 2 | quadratic | 17598702 | 9.437 | 8.38e-04 | 3.10e-03 | 3.74e-03 | -1.5e-03 |' '$page' && grep -q '| 0.50 | 1.82e-02 | 2 | 2.39e-02 | 2.14e-02 | 2.24e-02 |' '$page'"
check "beam: a case's row and the Fig. 10 measure" \
  "grep -q '| fig11 | 100 | 1.223 | 4.97e-04 | 1.44e-02 | 2.09e-01 | 0.912 | 5.20e-04 | 1.056 | 8.40e-04 | 1.981 (inside) | 1.62 | 1.07 |' '$page' && grep -q '| certified | 65536 | 100.0000% | 0.104 | 0 |' '$page'"
check "star: a slope row, a profile row and the bench row" \
  "grep -q '| 1.5 | 0 | 4.58e-09 | -N | 0.1482 | 0.482 | - |' '$page' && grep -q '| 0.02, 0.1 | 3.53e-03 | 1.0129 | 0.00e+00 |' '$page' && grep -q '| 512 | physical | 1 | 0.0412 | 0.0011 | 381 |' '$page'"
check "curves: default rows by curve, instructions where counted" \
  "grep -q '| 1000 | 4.027 | 4.195 | 1.042 | - |' '$page' && grep -q '| 0.05 | 1.170 | 0.426 | 0.363 | 0.243 |' '$page' && ! grep -q '| 1000 | 3.900 |' '$page'"
check "dispersion: the counts and a linearity row" \
  "grep -q '5248 cases compared' '$page' && grep -q 'off in 4085 of them' '$page' && grep -q '| 10 | 2.46e-02 | 1.04e-01 | 5.53e-04 | 8.24e-02 |' '$page'"

rm "$dir/out/verify-bounds.json" "$dir/out/fig10-1989.log"
echo '{"systems": ' >"$dir/out/figures/summary.json"   # truncated: unreadable
"$results" "$dir/out" -o "$page" >/dev/null 2>"$dir/err"; rc=$?
check "exit 0 with inputs missing" "[ $rc -eq 0 ]"
check "missing bounds: not run" \
  "grep -A2 'pencil verify bounds' '$page' | grep -q 'not run: .*verify-bounds.json. not found'"
check "missing Fig. 10 log: not run" "grep -q 'not run: fig10-1989.log not found' '$page'"
check "unreadable summary: figures and sweep not run" "[ \$(grep -c 'not run: .*summary.json. unreadable' '$page') -eq 2 ]"
check "matrices still reported" "grep -q '| 1234 | 56 | 0 | 3.25e-12 |' '$page'"
check "--help" "'$results' --help | grep -q 'usage: scripts/results'"
touch "$dir/plainfile"   # a file where a directory is needed: fails even for root
"$results" "$dir/out" -o "$dir/plainfile/r.md" >/dev/null 2>"$dir/err"; rc=$?
check "unwritable output: exit 1, named on stderr" "[ $rc -eq 1 ] && grep -q plainfile/r.md '$dir/err'"
finish cli_results
