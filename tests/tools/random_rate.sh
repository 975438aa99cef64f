#!/usr/bin/env bash
# The random-scene suite's large run (not part of CI: about 1.3 s of wall time per seed on
# 2 cores): COUNT seeds from FIRST through the suite's own test, two shards at a time, then the
# pass rate per rule, the failures by class and by feature (tests/tools/random_rate.py).
#   tests/tools/random_rate.sh BUILD_DIR FIRST COUNT OUT_DIR
# OUT_DIR gets report.md, the shards' logs and tables, the failing seeds' scenes and images
# (scenes/) and one scene per failing class (regressions/).
set -euo pipefail
if [ $# -ne 4 ]; then
  echo "usage: tests/tools/random_rate.sh BUILD_DIR FIRST COUNT OUT_DIR" >&2
  exit 2
fi
build=$(cd "$1" && pwd) first=$2 count=$3 out=$4
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
rm -f "$out"/report.shard*.tsv
export CANDELA_RANDOM_FIRST=$first CANDELA_RANDOM_SEEDS=$count CANDELA_RANDOM_REPORT=$out/report CANDELA_RANDOM_OUT=$out/scenes
# The suite's 8 shards, 2 processes at a time (one per core: llvmpipe is given one thread each).
seq 0 7 | xargs -P 2 -I{} sh -c "LP_NUM_THREADS=1 '$build/bin/unit_tests' --gtest_filter='Shards/RandomSceneTest.*/shard{}' > '$out/shard{}.log' 2>&1 || true"
/usr/bin/python3 "$here/random_rate.py" "$out/report" --scenes "$out/scenes" --regressions "$out/regressions" | tee "$out/report.md"
