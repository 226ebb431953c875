#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, builds tests/consumer against it with
# find_package(dhdr), runs it, and checks that no public header includes Embree, Assimp or
# OpenColorIO. Usage: tests/consumer/run.sh BUILD_DIR
set -euo pipefail
build=$1
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/dhdr_consumer_XXXXXX)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
test -f "$work/prefix/lib/cmake/dhdr/dhdrConfig.cmake"
test -x "$work/prefix/bin/dhdr-light"
if grep -rE '#include <(embree|assimp|OpenColorIO)' "$work/prefix/include"; then
  echo "consumer: a public header includes a heavy dependency" >&2
  exit 1
fi
cmake -S "$here" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/build" -j2 >/dev/null
"$work/build/consumer"
"$work/prefix/bin/dhdr-light" --version
# The Python module (built unless under the sanitizers), importable from the prefix's
# dist-packages (docs/python.md).
if [ -d "$build/python/dhdr" ]; then
  site=$(echo "$work"/prefix/lib/python3*/dist-packages)
  test -f "$site/dhdr/__init__.pyi"
  (cd "$work" && PYTHONPATH="$site" /usr/bin/python3 -c \
    'import dhdr, numpy; assert dhdr.tone_map(numpy.ones((2, 2, 3), numpy.float32)).width == 2')
fi
