#!/usr/bin/env bash
# Run the peer scenes (free_bodies, dzhanibekov, pyramid with sleeping off and on, ball_pit)
# in rigidrs and in the peer engines, REPS times, sequentially (repetitions outermost, so
# machine noise spreads over every engine), then write the medians and ratios with compare.py.
#
#   PEERS_DIR=/path/to/peer/scripts PEERS_PY=/venv-peers/bin/python RIGIDRS_PY=/venv/bin/python \
#       bash benches/peers/run_side_by_side.sh
#
# PEERS_DIR holds the peer-engine scripts (free_bodies.py, dzhanibekov.py, pyramid.py,
# ball_pit.py, common.py that take --engine mujoco|pybullet|rapier3d); PEERS_PY has numpy scipy mujoco pybullet rapier3d,
# RIGIDRS_PY has rigidrs (pip install .) and scipy. Engines that fail to import are skipped
# (their errors go to side_by_side.log). Output in OUT_DIR (default: a new temporary folder):
# results.jsonl (raw JSON lines), peer_versions.json, side_by_side.log (stderr), COMPARISON.md.
# CLOCK=cpu times every script with the process CPU clock instead of wall time (through
# cpu_clock.py), for a machine shared with other jobs.
# NumPy's OpenBLAS threads, started by every script's imports, busy-wait after a BLAS call
# and CLOCK=cpu counts them: OPENBLAS_NUM_THREADS defaults to 1 here, for every engine alike
# (none of the timed loops calls BLAS).
# SCENES (default "free_bodies dzhanibekov pyramid ball_pit") picks the scenes; also
# "large_pyramids" (bases 30 and 40, sleep off, Rapier and rigidrs only), "two_threads"
# (the pyramid and the ball pit with both engines on two threads, rigidrs on one too) and
# "box_pile" (4000 cubes dropped, 120 steps, Rapier and rigidrs, one thread and two; slow:
# about a minute a repetition) for the bars of the issue "Scale".
# RIGIDRS_CONTACT_VARIANTS: ';'-separated argument sets for rigidrs's pyramid and ball_pit
# (default ";--substeps 3;--substeps 2 --iterations 2": the defaults, 4 substeps x 1
# iteration; 3 x 1, the fewest substeps at which the pyramid comes to rest; 2 x 2, the
# cheapest setting under which it still stands, though it keeps jittering).
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
: "${PEERS_DIR:?set PEERS_DIR to the folder of the peer-engine scripts}"
PEERS_PY=${PEERS_PY:-python3}
RIGIDRS_PY=${RIGIDRS_PY:-python3}
REPS=${REPS:-3}
CLOCK=${CLOCK:-wall}
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
SCENES=${SCENES:-"free_bodies dzhanibekov pyramid ball_pit"}
RIGIDRS_CONTACT_VARIANTS=${RIGIDRS_CONTACT_VARIANTS-";--substeps 3;--substeps 2 --iterations 2"}
IFS=';' read -r -a RIGIDRS_VARIANTS <<< "$RIGIDRS_CONTACT_VARIANTS"
[ ${#RIGIDRS_VARIANTS[@]} -eq 0 ] && RIGIDRS_VARIANTS=("")
has() { [[ " $SCENES " == *" $1 "* ]]; }
OUT_DIR=${OUT_DIR:-$(mktemp -d)}
mkdir -p "$OUT_DIR"
OUT=$OUT_DIR/results.jsonl
LOG=$OUT_DIR/side_by_side.log
: > "$OUT"
: > "$LOG"

run() {  # run PY DIR SCRIPT ARGS...
    local py=$1 dir=$2; shift 2
    echo "+ $*" >> "$LOG"
    local launch=()
    [ "$CLOCK" = cpu ] && launch=("$HERE/cpu_clock.py")
    (cd "$dir" && "$py" "${launch[@]}" "$@" 2>> "$LOG" | grep '^{' >> "$OUT") || echo "  failed: $*" >> "$LOG"
}

"$PEERS_PY" -c "import json, sys; sys.path.insert(0, '$PEERS_DIR'); from common import versions; print(json.dumps(versions()))" \
    > "$OUT_DIR/peer_versions.json" 2>> "$LOG" || echo '{}' > "$OUT_DIR/peer_versions.json"
start=$(date +%s)
for rep in $(seq "$REPS"); do
    echo "rep $rep/$REPS ($(( $(date +%s) - start )) s)" >&2
    if has free_bodies; then
        for e in mujoco pybullet rapier3d; do
            run "$PEERS_PY" "$PEERS_DIR" free_bodies.py --engine "$e"
        done
        run "$PEERS_PY" "$PEERS_DIR" free_bodies.py --engine mujoco --mj-integrator RK4
        run "$RIGIDRS_PY" "$HERE" free_bodies.py --integrator all
    fi
    if has dzhanibekov; then
        for e in mujoco pybullet rapier3d; do
            run "$PEERS_PY" "$PEERS_DIR" dzhanibekov.py --engine "$e"
        done
        run "$RIGIDRS_PY" "$HERE" dzhanibekov.py --integrator all
    fi
    if has pyramid; then
        for sleep in 0 1; do
            for e in mujoco pybullet rapier3d; do
                run "$PEERS_PY" "$PEERS_DIR" pyramid.py --engine "$e" --sleep "$sleep"
            done
            for v in "${RIGIDRS_VARIANTS[@]}"; do
                # shellcheck disable=SC2086  # $v is a list of arguments
                run "$RIGIDRS_PY" "$HERE" pyramid.py --sleep "$sleep" $v
            done
        done
    fi
    if has ball_pit; then
        for e in mujoco pybullet rapier3d; do  # MuJoCo uses CG here (the peer script's default)
            run "$PEERS_PY" "$PEERS_DIR" ball_pit.py --engine "$e"
        done
        for v in "${RIGIDRS_VARIANTS[@]}"; do
            # shellcheck disable=SC2086
            run "$RIGIDRS_PY" "$HERE" ball_pit.py $v
        done
    fi
    if has large_pyramids; then
        for base in 30 40; do
            for t in 1 2; do
                run "$PEERS_PY" "$PEERS_DIR" pyramid.py --engine rapier3d --base "$base" --threads "$t"
                run "$RIGIDRS_PY" "$HERE" pyramid.py --base "$base" --threads "$t"
            done
        done
    fi
    if has two_threads; then
        run "$PEERS_PY" "$PEERS_DIR" pyramid.py --engine rapier3d --threads 2
        run "$PEERS_PY" "$PEERS_DIR" ball_pit.py --engine rapier3d --threads 2
        for t in 1 2; do
            run "$RIGIDRS_PY" "$HERE" pyramid.py --threads "$t"
            run "$RIGIDRS_PY" "$HERE" ball_pit.py --threads "$t"
        done
    fi
    if has box_pile; then
        for t in 1 2; do
            run "$PEERS_PY" "$HERE" box_pile.py --engine rapier3d --steps 120 --threads "$t"
            run "$RIGIDRS_PY" "$HERE" box_pile.py --engine rigidrs --steps 120 --threads "$t"
        done
    fi
done
"$RIGIDRS_PY" "$HERE/compare.py" "$OUT" --peer-versions "$OUT_DIR/peer_versions.json" --clock "$CLOCK" > "$OUT_DIR/COMPARISON.md"
echo "done in $(( $(date +%s) - start )) s; wrote $OUT_DIR/COMPARISON.md" >&2
