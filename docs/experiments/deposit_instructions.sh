#!/bin/bash
# Instructions run inside Paper::deposit (GL work included: llvmpipe rasterises in the calling
# thread with LP_NUM_THREADS=0) while batch_profile.py writes N characters at 1024 px (session 13).
# Deterministic for a given build, unlike times on this shared machine; ~70 s for N = 3.
#   docs/experiments/deposit_instructions.sh [PYTHONPATH] [N]
here=$(cd "$(dirname "$0")" && pwd)
pp=${1:-$here/../../python}
n=${2:-3}
out=$(mktemp -d)
py=$(python3 -c "import sys; print(sys.executable)")   # the interpreter itself, not a shim
LP_NUM_THREADS=0 OPENBLAS_NUM_THREADS=1 PYTHONPATH=$pp valgrind --tool=callgrind --trace-children=yes \
  --callgrind-out-file="$out/cg.%p" --toggle-collect='*Paper::deposit*' "$py" "$here/batch_profile.py" "$n" >/dev/null 2>&1
for f in "$out"/cg.*; do callgrind_annotate "$f" 2>/dev/null | grep "PROGRAM TOTALS"; done
rm -rf "$out"
