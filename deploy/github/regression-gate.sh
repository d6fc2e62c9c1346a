#!/bin/bash
# The regression gate of a pull request (deploy/github/regression.yml runs it; it runs the
# same anywhere):
#
#   deploy/github/regression-gate.sh BASE_CHECKOUT BASE_BIN HEAD_BIN OUT [report flags…]
#
# 1. BASE_BIN, the build of the base branch checked out in BASE_CHECKOUT, measures the base on
#    this machine, in that checkout (so the report names the base commit): OUT/base/.
# 2. HEAD_BIN, the build of the pull request (the current folder), measures the head: OUT/head/,
#    whose page lists the changes against the base (--baseline OUT/base/metrics.json) and shows
#    the trends of the base branch's history BASE_CHECKOUT/results/history followed by this
#    run (--history); the run is recorded in OUT/head/history/.
# 3. Quality: `compare OUT/base/metrics.json OUT/head/metrics.json` — its exit code is the
#    gate's (1: a quality figure got worse).
# 4. Timings: `compare --timings` of the same two reports, measured one after the other on this
#    machine; printed (and appended to $GITHUB_STEP_SUMMARY when set), never failing the gate.
#
# Paths in the report flags must be absolute (the base runs in BASE_CHECKOUT). OUT must not
# exist yet or hold an earlier gate's output.
set -uo pipefail
usage="usage: regression-gate.sh BASE_CHECKOUT BASE_BIN HEAD_BIN OUT [report flags…]"
base_checkout="${1:?$usage}"
base_bin="${2:?$usage}"
head_bin="${3:?$usage}"
out="${4:?$usage}"
shift 4
mkdir -p "$out" || exit 2
out="$(cd "$out" && pwd)"
base_bin="$(cd "$(dirname "$base_bin")" && pwd)/$(basename "$base_bin")"

echo "== base: $base_checkout"
(cd "$base_checkout" && "$base_bin" report --out "$out/base" "$@") || exit 2

echo "== head"
history=()
if [ -d "$base_checkout/results/history" ]; then
    history=(--history "$base_checkout/results/history")
fi
"$head_bin" report --out "$out/head" --baseline "$out/base/metrics.json" "${history[@]}" "$@" \
    || exit 2

echo "== quality (the gate)"
"$head_bin" compare "$out/base/metrics.json" "$out/head/metrics.json" | tee "$out/quality.txt"
quality=${PIPESTATUS[0]}

echo "== timings (same machine, reported only)"
"$head_bin" compare --timings "$out/base/metrics.json" "$out/head/metrics.json" \
    | grep -E '_ms |^note: |^no changes|regression\(s\)' | tee "$out/timings.txt"

if [ -n "${GITHUB_STEP_SUMMARY:-}" ]; then
    {
        echo "### smoothlab regression gate"
        echo '```'
        cat "$out/quality.txt"
        echo '```'
        echo "Timings, base and head measured on this runner (not gating):"
        echo '```'
        cat "$out/timings.txt"
        echo '```'
    } >> "$GITHUB_STEP_SUMMARY"
fi
if [ "$quality" -ne 0 ]; then
    echo "gate: quality regression (exit $quality); the page is $out/head/index.html"
else
    echo "gate: no quality regression; the page is $out/head/index.html"
fi
exit "$quality"
