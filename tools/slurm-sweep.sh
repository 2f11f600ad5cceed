#!/usr/bin/env bash
# Submits a sweep to Slurm: an array job with one `sdfbrick sweep --shard i/n` per task, and a merge
# job that starts when every task has succeeded (afterok) and joins the shards into PREFIX.csv and
# PREFIX.json (docs/sweep.md, "Sweeps on Slurm").
#
#   tools/slurm-sweep.sh --shards N --out PREFIX [--sdfbrick PATH] [--sbatch ARG]... -- SWEEP-ARGS...
#
# SWEEP-ARGS are `sdfbrick sweep`'s (a sweep file and/or flags; -d picks each node's devices). Shard i
# writes PREFIX.shard-i.{csv,json,log}; the merge writes PREFIX.merge.log. Every --sbatch ARG is passed
# to both sbatch calls (e.g. --sbatch --partition=gpu --sbatch --gres=gpu:1). Prints "array JOBID"
# and "merge JOBID". Exit 2 for bad usage or when Slurm's sbatch is not installed.
set -euo pipefail

usage="usage: tools/slurm-sweep.sh --shards N --out PREFIX [--sdfbrick PATH] [--sbatch ARG]... -- SWEEP-ARGS..."
fail() { echo "slurm-sweep: $1" >&2; exit 2; }

shards="" out="" bin="sdfbrick"
sbatch_args=()
while (($#)); do
    case $1 in
        --shards) (($# >= 2)) || fail "--shards needs a value ($usage)"; shards=$2; shift 2 ;;
        --out) (($# >= 2)) || fail "--out needs a value ($usage)"; out=$2; shift 2 ;;
        --sdfbrick) (($# >= 2)) || fail "--sdfbrick needs a value ($usage)"; bin=$2; shift 2 ;;
        --sbatch) (($# >= 2)) || fail "--sbatch needs a value ($usage)"; sbatch_args+=("$2"); shift 2 ;;
        --) shift; break ;;
        *) fail "unknown option $1 ($usage)" ;;
    esac
done
[[ $shards =~ ^[1-9][0-9]*$ ]] || fail "--shards must be a positive integer, got \"$shards\""
[[ -n $out ]] || fail "--out PREFIX is required ($usage)"
command -v sbatch > /dev/null || fail "sbatch not found: Slurm is not installed here (Debian: apt-get install slurm-client)"
bin_path=$(command -v "$bin") || fail "--sdfbrick: $bin not found"
bin_path=$(realpath "$bin_path")
out=$(realpath -m "$out")
mkdir -p "$(dirname "$out")"

(($# > 0)) || fail "no sweep arguments after -- ($usage)"
sweep=$(printf '%q ' "$@")
q_bin=$(printf '%q' "$bin_path")
q_out=$(printf '%q' "$out")
array=$(sbatch --parsable --array="0-$((shards - 1))" --job-name=sdfbrick-sweep --output="$out.shard-%a.log" \
    "${sbatch_args[@]+"${sbatch_args[@]}"}" \
    --wrap "$q_bin sweep $sweep --shard \$SLURM_ARRAY_TASK_ID/$shards --out $q_out.shard-\$SLURM_ARRAY_TASK_ID")
array=${array%%;*}
shard_files=""
for ((i = 0; i < shards; ++i)); do shard_files+=" $q_out.shard-$i.json"; done
merge=$(sbatch --parsable --dependency="afterok:$array" --job-name=sdfbrick-merge --output="$out.merge.log" \
    "${sbatch_args[@]+"${sbatch_args[@]}"}" --wrap "$q_bin merge$shard_files --out $q_out")
merge=${merge%%;*}
echo "array $array"
echo "merge $merge"
