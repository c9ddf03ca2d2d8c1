#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs the build into a temporary prefix and uses it as an adopter would: builds and runs a
# consumer project with find_package(MorphMill), compiles one with pkg-config, runs the installed
# morphmill, renders its man page, imports the installed Python module.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd) source=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" > "$work/install.log"
echo "installed into $prefix: $(find "$prefix" -type f | wc -l) files"
for file in bin/morphmill share/man/man1/morphmill.1 include/morph/erode.h include/vdb_ref/reference.h \
            include/raytest/deviation.h; do
  [[ -f $prefix/$file ]] || { echo "missing after install: $file"; exit 1; }
done
libdir=$(dirname "$(find "$prefix" -name MorphMillConfig.cmake -printf '%h')")  # .../lib/cmake
libdir=$(dirname "$libdir")

# The installed program runs from its prefix, and says its version.
version=$("$prefix/bin/morphmill" --version)
[[ $version == "morphmill "* ]] || { echo "unexpected --version output: $version"; exit 1; }
echo "$version"

# The man page renders without warnings.
warnings=$(groff -man -Tutf8 -ww -z "$prefix/share/man/man1/morphmill.1" 2>&1)
[[ -z $warnings ]] || { echo "man page warnings: $warnings"; exit 1; }
MANWIDTH=80 man -l "$prefix/share/man/man1/morphmill.1" 2>/dev/null | grep -q "EXIT STATUS" || {
  echo "man -l did not render the page"; exit 1; }

# find_package(MorphMill) from a project outside the tree.
cmake -S "$source/tests/install/consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$prefix" -DMORPHMILL_EXAMPLES_DIR="$source/examples" ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER} \
      > "$work/consumer-configure.log" || { cat "$work/consumer-configure.log"; exit 1; }
cmake --build "$work/consumer" -j 2 > "$work/consumer-build.log" || { cat "$work/consumer-build.log"; exit 1; }
"$work/consumer/consumer"
"$work/consumer/verify_a_job" "$source/data/jobs/single_slot.json" 0.5 | tee "$work/verify.log"
grep -q "verify: holds" "$work/verify.log"

# pkg-config: the same program, flags from morphmill.pc.
export PKG_CONFIG_PATH=$libdir/pkgconfig
flags=$(pkg-config --cflags --libs morphmill)
${CXX:-c++} -std=c++17 -O1 "$source/tests/install/consumer/consumer.cpp" -o "$work/consumer_pc" $flags
"$work/consumer_pc"
# The Python module from the prefix (where it was built with Python).
if module=$(find "$prefix" -name 'morphmill*.so' -path '*dist-packages*' | head -n 1) && [[ -n $module ]]; then
  # A sanitized build's module needs its runtimes loaded first (MORPHMILL_PYTHON_PRELOAD, set by ctest).
  PYTHONPATH=$(dirname "$module") ${MORPHMILL_PYTHON_PRELOAD:+env LD_PRELOAD=$MORPHMILL_PYTHON_PRELOAD ASAN_OPTIONS=detect_leaks=0} "${PYTHON:-/usr/bin/python3}" -c \
    "import morphmill; v = morphmill.version(); assert v == '${version#morphmill }', v; print('python: morphmill', v)"
fi
echo "install test: ok"
