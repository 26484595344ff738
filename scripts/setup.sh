#!/usr/bin/env bash
# Set up stripebench on a fresh machine: a virtual environment in .venv with the
# package and its test extras, and (when we can) Debian's libLLVM 19, which
# Mitsuba's fast `llvm_*` variants need (with LLVM 14/15 they abort; without a
# working LLVM stripebench falls back to the ~4x slower scalar variant).
# Then it compiles the kernels (scripts/compile_kernels.py). Idempotent: a second run only checks.
set -euo pipefail
cd "$(dirname "$0")/.."

# The environment takes about 2.4 GB (JAX, Mitsuba, VTK), and pip needs about as much again in its
# temporary folder while it installs (less when that is on another disk). Below 3 GB free it cannot
# succeed: say so in one line and stop, before pip fails half-way with "No space left on device".
free_mb() { df -Pm "$1" 2>/dev/null | awk 'NR == 2 {print $4}'; }
need_mb=${STRIPEBENCH_SETUP_NEED_MB:-3000}
if [ ! -x .venv/bin/stripebench ]; then
    for dir in . "${TMPDIR:-/tmp}"; do
        have=$(free_mb "$dir")
        if [ -n "$have" ] && [ "$have" -lt "$need_mb" ]; then
            echo "setup: only ${have} MB free on $(cd "$dir" && pwd) (set-up needs at least ${need_mb} MB: the environment takes about 2.4 GB);" \
                 "free some space${TMPDIR:+ or point TMPDIR elsewhere}" >&2
            exit 2
        fi
    done
fi

have_llvm19() { ldconfig -p 2>/dev/null | grep -q 'libLLVM\(-19\|\.so\.19\)'; }
# apt-get "$@", quietly; while another apt or dpkg holds its lock (an unattended upgrade, a second set-up),
# wait and try again, up to $STRIPEBENCH_SETUP_APT_WAIT_S seconds (default 120). On failure apt_said holds
# the last two lines apt printed, for the one line that says why.
apt_said=""
apt_try() {
    local waited=0 wait_s=${STRIPEBENCH_SETUP_APT_WAIT_S:-120} out
    while :; do
        if out=$(apt-get "$@" 2>&1); then
            return 0
        fi
        if printf '%s\n' "$out" | grep -qi 'could not get lock\|unable to acquire\|is another process using it'; then
            if [ "$waited" -lt "$wait_s" ]; then
                [ "$waited" = 0 ] && echo "setup: apt is busy (another apt or dpkg holds its lock); waiting up to ${wait_s} s"
                sleep 2
                waited=$((waited + 2))
                continue
            fi
        fi
        apt_said=$(printf '%s\n' "$out" | grep -v '^[[:space:]]*$' | tail -n 2 | tr '\n' ' ' | sed 's/ *$//')
        return 1
    done
}
if ! have_llvm19; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "setup: installing libllvm19 (for Mitsuba's LLVM variants)"
        if ! { apt_try install -y -qq libllvm19 || { apt_try update -qq && apt_try install -y -qq libllvm19; }; }; then
            echo "setup: could not install libllvm19 (apt-get: ${apt_said:-no message}); rendering will use a" \
                 "slower Mitsuba variant"
        fi
    else
        echo "setup: libLLVM 19 not found and not root; rendering will use a slower Mitsuba variant" \
             "(install Debian's libllvm19 to speed it up)"
    fi
fi

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
    "$PY" -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip >/dev/null
.venv/bin/python -m pip install -q -e '.[test]'
# Compile the trackers' numba kernels (cached beside their source) and the renderer's Dr.Jit kernels (cached in
# ~/.drjit) once, as building an extension is part of installing it; the stamp names the home whose cache holds them.
stamp=.venv/.stripebench-kernels
if [ "$(cat "$stamp" 2>/dev/null)" != "$HOME" ]; then
    echo "setup: compiling the trackers' and the renderer's kernels (about 2 min on a 2-core machine, once)"
    .venv/bin/python scripts/compile_kernels.py
    printf '%s' "$HOME" > "$stamp"
fi
echo "setup: ready (.venv/bin/stripebench)"
