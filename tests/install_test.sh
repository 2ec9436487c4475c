#!/usr/bin/env bash
# ctest `install_package` (label `install`, issue 13): installs the build
# tree into a temporary prefix with `cmake --install`, checks the installed
# tree (libraries, headers whose includes all resolve inside it, every app
# of apps/, the CMake package with no path back into the source or build
# tree), then configures and builds tests/consumer against it with
# find_package(servo_axis_id) and runs it, and runs the installed
# simulate-axis. Exits non-zero on the first failure, saying what.
#   install_test.sh CMAKE BUILD_DIR SOURCE_DIR CXX_COMPILER [LINKER_FLAGS]
set -euo pipefail
cmake=$1 build=$2 source=$3 cxx=$4 link_flags=${5:-}
work=$(mktemp -d "${TMPDIR:-/tmp}/servo_axis_id_install.XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix
fail() { echo "install test: $*" >&2; exit 1; }
run_logged() {  # NAME COMMAND...: runs COMMAND, its output in $work/NAME.log, shown on failure
  local name=$1; shift
  "$@" > "$work/$name.log" 2>&1 || { cat "$work/$name.log" >&2; fail "$name failed: $*"; }
}

run_logged install "$cmake" --install "$build" --prefix "$prefix"

# The package files, wherever GNUInstallDirs put the library folder.
config=$(find "$prefix" -name servo_axis_idConfig.cmake -print -quit)
[[ -n $config ]] || fail "no servo_axis_idConfig.cmake under $prefix"
package_dir=$(dirname "$config")
for f in servo_axis_idConfigVersion.cmake servo_axis_idTargets.cmake system_libraries.cmake; do
  [[ -f $package_dir/$f ]] || fail "no $f beside $config"
done
for lib in servo_axis_id_io servo_axis_id_sim servo_axis_id_common servo_axis_id_estimation servo_axis_id_discovery servo_axis_id_design servo_axis_id_report servo_axis_id_run servo_axis_id_fleet; do
  [[ -n $(find "$prefix" -name "lib$lib.*" -print -quit) ]] || fail "library $lib not installed"
done
if grep -rlF -e "$source" -e "$build" "$package_dir"; then
  fail "the installed CMake package refers to the source or build tree (files above)"
fi

# Headers: the layer folders, each project include found in the prefix.
for h in sim/simulate.h io/mat_file.h estimation/fit.h run/fit_job.h; do
  [[ -f $prefix/include/$h ]] || fail "header $h not installed"
done
# The public API only: no layer's internal/ headers (tests/layering_test.py).
if [[ -n $(find "$prefix/include" -path '*/internal/*' -print -quit) ]]; then
  fail "internal headers installed: $(find "$prefix/include" -path '*/internal/*' | head -3)"
fi
while IFS= read -r line; do
  header=${line%%:*}
  included=$(sed -E 's/.*#include "([^"]+)".*/\1/' <<< "${line#*:}")
  [[ -f $prefix/include/$included ]] || fail "$header includes $included, not installed"
done < <(grep -rE '^#include "' "$prefix/include")

# Every app of apps/.
for app in $(sed -nE 's/^add_executable\(([^ ]+) .*/\1/p' "$source/apps/CMakeLists.txt"); do
  [[ -x $prefix/bin/$app ]] || fail "app $app not installed in $prefix/bin"
done

# A project of its own against the installed package only.
run_logged configure "$cmake" -S "$source/tests/consumer" -B "$work/consumer" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
  -DCMAKE_EXE_LINKER_FLAGS="$link_flags"
run_logged build "$cmake" --build "$work/consumer" -j 1
"$work/consumer/consumer" "$source/configs/axes/x_axis.yaml" || fail "the consumer failed"

# The installed simulate-axis: Fig. 4's experiment, 1.5 s at 1 kHz.
run_logged simulate "$prefix/bin/simulate-axis" "$source/configs/experiments/x_step_10V.yaml" \
  --out "$work/trace.csv" --no-noise
lines=$(wc -l < "$work/trace.csv")
[[ $lines -eq 1502 ]] || fail "simulate-axis wrote $lines lines, expected 1502 (header + 1501)"
echo "install test: installed into a temporary prefix, built and ran the consumer and simulate-axis"
