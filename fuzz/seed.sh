#!/usr/bin/env bash
# Refresh the seed corpora: `config` from the shipped configs, `table` from
# the replayed tables and the head of a real packing.csv, `checkpoint` from
# real checkpoints (`seed_checkpoints` stops a search after generations 1-3).
# Seeds are named seed_*; entries libFuzzer adds are not committed.
set -euo pipefail
cd "$(dirname "$0")"
mkdir -p corpus/config corpus/table corpus/checkpoint
rm -f corpus/config/seed_* corpus/table/seed_* corpus/checkpoint/seed_*
for f in ../configs/*.toml; do
  cp "$f" "corpus/config/seed_$(basename "$f")"
done
for f in ../tests/data/replay/table/*.csv; do
  cp "$f" "corpus/table/seed_$(basename "$f")"
done
cargo run --quiet --release --bin seed_checkpoints
ls corpus/*/seed_* | wc -l
