#!/bin/bash
# Alternates `squeal bench explicit` between binaries, so that drift of a shared machine hits
# all of them alike, and prints min and median per binary.
# usage: benches/explicit_ab.sh THREADS ROUNDS BINARY...   (e.g. target/release/squeal /tmp/old)
set -euo pipefail
if [ $# -lt 3 ] || ! [[ $1 =~ ^[1-9][0-9]*$ ]] || ! [[ $2 =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 THREADS ROUNDS BINARY... (THREADS and ROUNDS: positive integers)" >&2
  exit 2
fi
threads=$1
rounds=$2
shift 2
tmp=$(mktemp -d)
for i in $(seq "$rounds"); do
  for k in $(seq $#); do
    bin=${!k}
    "$bin" bench explicit --elements 100000 --threads "$threads" 2>&1 |
      awk -F= '/^element_loop_ns_per_element/{e=$2} /^ns_per_element_step/{s=$2} END{print e, s}' \
      >>"$tmp/$k"
  done
done
median() { sort -g | awk '{v[NR]=$1} END{if (NR%2) print v[(NR+1)/2]; else print (v[NR/2]+v[NR/2+1])/2}'; }
for k in $(seq $#); do
  bin=${!k}
  el_min=$(cut -d' ' -f1 "$tmp/$k" | sort -g | head -1)
  el_med=$(cut -d' ' -f1 "$tmp/$k" | median)
  st_min=$(cut -d' ' -f2 "$tmp/$k" | sort -g | head -1)
  st_med=$(cut -d' ' -f2 "$tmp/$k" | median)
  echo "$bin threads=$threads element_loop min $el_min median $el_med | step min $st_min median $st_med"
done
rm -r "$tmp"
