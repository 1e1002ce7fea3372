#!/bin/bash
# Submits a tiled render to Slurm: an array of N tile tasks and a merge job that runs only
# if all of them succeed. Prints the two job ids ("ARRAY_ID MERGE_ID").
#   SCENE=scene.scn N=16 OUT_DIR=/shared/parts OUTPUT=/shared/final.png [SCNC=…] \
#     [SCNC_ARGS="--spp 256"] [SBATCH_ARGS="--partition=render"] ./submit.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${SCENE:?}" "${N:?}" "${OUT_DIR:?}" "${OUTPUT:?}"
mkdir -p "$OUT_DIR"
export SCENE N OUT_DIR OUTPUT SCNC="${SCNC:-scnc}" SCNC_ARGS="${SCNC_ARGS:-}"
# shellcheck disable=SC2086
array=$(sbatch --parsable ${SBATCH_ARGS:-} --export=ALL --array="0-$((N - 1))" \
    --output="$OUT_DIR/tile_%a.log" "$here/render-tile.sbatch")
array="${array%%;*}"
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_ARGS:-} --export=ALL --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes --output="$OUT_DIR/merge.log" "$here/merge.sbatch")
echo "$array ${merge%%;*}"
