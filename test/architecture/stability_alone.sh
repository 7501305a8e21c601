#!/bin/sh
# Runs the program linked against scw::stability alone and checks that its binary needs none of
# the libraries the rest of the workspace uses. Usage: stability_alone.sh BINARY
set -eu
bin=$1
"$bin"
if command -v ldd >/dev/null 2>&1; then
  libs=$(ldd "$bin")
  if echo "$libs" | grep -Ei 'ipopt|coinmumps|yaml|nlopt|libmpi' >/dev/null; then
    echo "stability_alone: the binary links a library the car's controller must not need:" >&2
    echo "$libs" | grep -Ei 'ipopt|coinmumps|yaml|nlopt|libmpi' >&2
    exit 1
  fi
fi
echo "stability_alone: links scw::stability alone"
