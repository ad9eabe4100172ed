#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# expect_exit.sh CODE TEXT COMMAND [ARG...]
# Runs COMMAND and passes only if it exits with exactly CODE (a crash or a signal never
# matches) and its stderr contains TEXT (a fixed string). Prints what it got otherwise.
set -u
if [ $# -lt 3 ]; then
    echo "usage: expect_exit.sh CODE TEXT COMMAND [ARG...]" >&2
    exit 2
fi
want_code=$1
want_text=$2
shift 2
err_file=$(mktemp)
trap 'rm -f "$err_file"' EXIT
"$@" 2>"$err_file"
code=$?
status=0
if [ "$code" != "$want_code" ]; then
    echo "expect_exit: exit code $code, expected $want_code: $*" >&2
    status=1
fi
if ! grep -qF -- "$want_text" "$err_file"; then
    echo "expect_exit: stderr lacks \"$want_text\"" >&2
    status=1
fi
if [ "$status" != 0 ]; then
    echo "--- stderr of the command:" >&2
    cat "$err_file" >&2
fi
exit "$status"
