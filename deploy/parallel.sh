#!/bin/bash
# A sharded smoothlab report with GNU parallel, on this machine or over ssh hosts:
#
#   deploy/parallel.sh N OUT MESHES [report flags…]
#
# runs the N shards (at most as many at once as parallel's -j allows, default one per core;
# with PARALLEL_HOSTS=hosts.txt, over the ssh hosts listed there — OUT and MESHES must then be
# on a file system every host sees, at the same path), then merges them into OUT. The one line
# it runs is:
#
#   parallel --will-cite smoothlab report --meshes MESHES --shard {}/N --out OUT/shards/{} ::: 0 … N-1 \
#     ; smoothlab merge OUT/shards/* -o OUT
#
# The cells of a figure go the same way, the parts beside the figure's output STEM:
#
#   parallel --will-cite smoothlab figure SPEC.toml --shard {}/N ::: 0 … N-1 \
#     ; smoothlab merge STEM.shard-*-of-N.json -o STEM
set -uo pipefail
n="${1:?usage: parallel.sh N OUT MESHES [report flags…]}"
out="${2:?usage: parallel.sh N OUT MESHES [report flags…]}"
meshes="${3:?usage: parallel.sh N OUT MESHES [report flags…]}"
shift 3
smoothlab="${SMOOTHLAB:-smoothlab}"
hosts=()
if [ -n "${PARALLEL_HOSTS:-}" ]; then hosts=(--sshloginfile "$PARALLEL_HOSTS" --workdir .); fi
parallel --will-cite --halt never "${hosts[@]}" \
    "$smoothlab" report --meshes "$meshes" "$@" --shard "{}/$n" --out "$out/shards/{}" \
    ::: $(seq 0 $((n - 1)))
# A failed shard leaves no part: merge names it and exits with 1.
parts=()
for ((i = 0; i < n; i++)); do [ -e "$out/shards/$i/partial.json" ] && parts+=("$out/shards/$i"); done
exec "$smoothlab" merge "${parts[@]}" -o "$out"
