#!/usr/bin/env bash
# Submits a tiled render: the tile array, then the merge once every tile succeeded.
#   SCNC=/path/to/scnc SCENE=scene.scn N=16 OUT=/shared/run1 ./submit.sh [extra sbatch flags]
# Prints the merge job's id (wait for it with `squeue -j ID` / `sacct -j ID`).
# Animation instead: FIRST=0 LAST=239 CHUNK=10 ./submit.sh --frames  (one task per chunk).
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
: "${SCENE:?set SCENE}" "${OUT:?set OUT}"
mkdir -p "$OUT"
export SCNC="${SCNC:-scnc}" SCENE OUT
if [ "${1:-}" = "--frames" ]; then
  shift
  : "${FIRST:?set FIRST}" "${LAST:?set LAST}" "${CHUNK:?set CHUNK}"
  export FIRST LAST CHUNK
  CHUNKS=$(( (LAST - FIRST + CHUNK) / CHUNK ))
  sbatch --parsable --chdir="$OUT" --array="0-$((CHUNKS - 1))" "$@" "$HERE/frames.sbatch"
  exit 0
fi
: "${N:?set N}"
export N
TILES=$(sbatch --parsable --chdir="$OUT" --array="0-$((N - 1))" "$@" "$HERE/tile.sbatch")
TILES="${TILES%%;*}"   # "jobid;cluster" on multi-cluster setups
sbatch --parsable --chdir="$OUT" --dependency="afterok:$TILES" --kill-on-invalid-dep=yes "$@" \
  "$HERE/merge.sbatch"
