#!/usr/bin/env bash
# Refresh the seed corpus of the `config` target from the shipped configs.
# Seeds are named seed_<config>.toml; entries libFuzzer adds are not committed.
set -euo pipefail
cd "$(dirname "$0")"
mkdir -p corpus/config
rm -f corpus/config/seed_*
for f in ../configs/*.toml; do
  cp "$f" "corpus/config/seed_$(basename "$f")"
done
ls corpus/config/seed_* | wc -l
