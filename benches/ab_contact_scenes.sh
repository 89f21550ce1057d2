#!/usr/bin/env bash
# A/B of a change on the contact scenes of examples/contact_scenes.rs: the
# example built at BASE (a git revision) and at the working tree, run
# alternately REPS times each, one run's state hash and every run's steps/s.
#
#   benches/ab_contact_scenes.sh BASE [SCENE] [STEPS] [REPS]
#
# SCENE: pyramid, pyramid_30, pyramid_35, pyramid_40, ball_pit, ball_pit_300,
# ball_pit_3000, box_pile, box_pile_4000 (default ball_pit); STEPS default 600;
# REPS default 5; THREADS (environment) default 1. Equal hashes: the change
# keeps the scene's bits. Runs alternate so that the machine's drift falls on
# both builds alike; on the 2-core machine a change under 3 % is within the
# spread of means of five runs.
set -euo pipefail
base=${1:?usage: $0 BASE [SCENE] [STEPS] [REPS]}
scene=${2:-ball_pit}
steps=${3:-600}
reps=${4:-5}
root=$(git rev-parse --show-toplevel)
work="$root/target/ab"
mkdir -p "$work"
rev=$(git -C "$root" rev-parse --verify "$base^{commit}")
if [ ! -d "$work/base" ]; then
    git -C "$root" worktree add --detach "$work/base" "$rev" >/dev/null
else
    git -C "$work/base" checkout -q --detach "$rev"
fi
# Each build in its own target directory: sharing one, the second build's
# example could be left as the first had uplifted it (both builds then ran
# the base, and gave its hash twice).
build() { (cd "$1" && CARGO_TARGET_DIR="$2" cargo build -q --profile dist --example contact_scenes) && cp "$2/dist/examples/contact_scenes" "$3"; }
build "$work/base" "$work/target-base" "$work/cs_base"
build "$root" "$work/target-new" "$work/cs_new"
export THREADS=${THREADS:-1} WINDOW=100000000
for b in base new; do
    echo "$b: $("$work/cs_$b" "$scene" "$steps" | grep -oE 'state [0-9a-f]+')"
done
for _ in $(seq "$reps"); do
    for b in base new; do
        echo "$b $("$work/cs_$b" "$scene" "$steps" | grep -oE '[0-9]+ steps/s' | cut -d' ' -f1)"
    done
done | awk '{s[$1] += $2; n[$1]++; if ($2 > m[$1]) m[$1] = $2}
    END {for (k in s) printf "%s: mean %.1f steps/s, best %d (%d runs)\n", k, s[k] / n[k], m[k], n[k]}' | sort
