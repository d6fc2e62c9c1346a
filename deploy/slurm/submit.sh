#!/bin/bash
# Submits a sharded smoothlab report as a Slurm job array of N tasks and a merge job that
# starts when every task has ended:
#
#   deploy/slurm/submit.sh N OUT MESHES [report flags…]
#
# e.g. `deploy/slurm/submit.sh 16 results data/meshes --scheme all` writes the shards to
# OUT/shards/0 … OUT/shards/15 and the merged report to OUT/. Set SMOOTHLAB to the binary's
# path if it is not on the PATH of the compute nodes; OUT must be on a shared file system.
set -euo pipefail
n="${1:?usage: submit.sh N OUT MESHES [report flags…]}"
out="${2:?usage: submit.sh N OUT MESHES [report flags…]}"
meshes="${3:?usage: submit.sh N OUT MESHES [report flags…]}"
shift 3
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$out/shards"
array=$(sbatch --parsable --array="0-$((n - 1))" "$here/shard.sbatch" \
    report --meshes "$meshes" "$@" --out "$out/shards/{}")
merge=$(sbatch --parsable --dependency="afterany:${array%%;*}" "$here/merge.sbatch" \
    "$out" "$out/shards/*/partial.json")
echo "array job $array ($n shards), merge job $merge -> $out"
