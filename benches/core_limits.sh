#!/usr/bin/env bash
# What the machine's cores can do for the explicit element update (issue 24's speed targets,
# docs/performance.md "What bounds a `paper` case on two cores"):
#   1. instructions per element-step of `squeal bench explicit` (element loop and node update),
#      counted by valgrind's callgrind as the difference of two runs (STEPS_B - STEPS_A steps),
#      so the mesh build and set-up cancel; callgrind counts instructions, not seconds, so the
#      figure does not depend on what else the machine is doing;
#   2. the memory bandwidth of a STREAM-like triad c = a + 3 b over 3 x 320 MB (gcc -O3 -fopenmp,
#      best of 10), on 1 and 2 threads.
#
#   benches/core_limits.sh [SQUEAL_BINARY]     (default target/release/squeal)
set -euo pipefail
cd "$(dirname "$0")/.."
squeal="${1:-target/release/squeal}"
if [ ! -x "$squeal" ]; then
  echo "core_limits: no executable squeal binary at $squeal (build it with cargo build --release, or pass its path)" >&2
  exit 2
fi
for tool in valgrind gcc; do
  command -v "$tool" > /dev/null || { echo "core_limits: $tool is needed and not installed" >&2; exit 2; }
done
elements=20000
steps_a=10
steps_b=30
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
count() {
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.$1" "$squeal" bench explicit \
    --elements "$elements" --threads 1 --steps "$1" > "$tmp/out.$1" 2> "$tmp/err.$1"
  grep -o 'refs: *[0-9,]*' "$tmp/err.$1" | tr -d ', ' | cut -d: -f2
}
ia=$(count $steps_a)
ib=$(count $steps_b)
n=$(grep -o 'elements=[0-9]*' "$tmp/out.$steps_a" | cut -d= -f2)
echo "elements=$n instructions_per_element_step=$(( (ib - ia) / ((steps_b - steps_a) * n) ))"
cat > "$tmp/triad.c" <<'C'
#include <stdio.h>
#include <stdlib.h>
#include <omp.h>
#define N (40L * 1000 * 1000)
int main(void) {
  double *a = malloc(N * 8), *b = malloc(N * 8), *c = malloc(N * 8);
#pragma omp parallel for
  for (long i = 0; i < N; i++) { a[i] = 1; b[i] = 2; c[i] = 0; }
  double best = 1e9;
  for (int r = 0; r < 10; r++) {
    double t = omp_get_wtime();
#pragma omp parallel for
    for (long i = 0; i < N; i++) c[i] = a[i] + 3.0 * b[i];
    t = omp_get_wtime() - t;
    if (t < best) best = t;
  }
  printf("threads=%d triad_gb_per_s=%.1f (check %.0f)\n", omp_get_max_threads(), 3.0 * N * 8 / best / 1e9, c[N / 2]);
  return 0;
}
C
gcc -O3 -march=native -fopenmp "$tmp/triad.c" -o "$tmp/triad"
OMP_NUM_THREADS=1 "$tmp/triad"
OMP_NUM_THREADS=2 "$tmp/triad"
