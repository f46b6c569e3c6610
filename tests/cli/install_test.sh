#!/bin/bash
# ctest cli.install_tree: `cmake --install` of the build into a temporary
# prefix puts the programs in P/bin, the docs in P/share/doc/mb2co, the EDS
# files in P/share/mb2co and the completion in
# P/share/bash-completion/completions; the installed mb2co-timing runs.
# Usage: install_test.sh BUILD_DIR
set -euo pipefail
build=$1
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
failed=0
for f in bin/mb2co-timing bin/mb2co-lab bin/mb2co-od share/doc/mb2co/cli.md share/doc/mb2co/timing.md \
         share/doc/mb2co/README.md share/mb2co/mb2co-ionode.eds share/mb2co/mb2co-gateway.eds \
         share/bash-completion/completions/mb2co-timing; do
  [[ -s $prefix/$f ]] || { echo "install_test: $f missing" >&2; failed=1; }
done
[[ -x $prefix/bin/mb2co-timing ]] || { echo "install_test: bin/mb2co-timing not executable" >&2; exit 1; }
version=$(sed -n 's/^project(mb2co VERSION \([0-9.]*\).*/\1/p' "$(dirname "$0")/../../CMakeLists.txt")
got=$(cd / && "$prefix/bin/mb2co-timing" --version)
[[ $got == "mb2co-timing $version" ]] || { echo "install_test: --version printed '$got'" >&2; failed=1; }
# The installed program works away from the build tree.
(cd / && "$prefix/bin/mb2co-timing" rta --line 3 --bitrate 500k >/dev/null) || { echo "install_test: rta failed" >&2; failed=1; }
exit $failed
