#!/usr/bin/env bash
# Peak memory of `gapack serve` while ten clients download a large job's
# packing.csv at once, and while ten fetch its drawn packing view.
#
#   serve/bench/download_rss.sh BINARY DATA_DIR [JOB_ID]
#
# Without JOB_ID, packs a 2130 x 2130 mm square of disks of radius 1 to 2 mm
# (about 2.0e6 disks, packing.csv only) first and prints its id; with it,
# reuses that job of DATA_DIR (so two binaries can be measured on one job).
# For each endpoint: the server's VmRSS when idle, then its peak (VmHWM,
# reset through /proc/PID/clear_refs) over the ten downloads, in kB.
set -euo pipefail
bin=$1
data=$2
job=${3:-}
mkdir -p "$data"
out=$(mktemp)
"$bin" serve --listen 127.0.0.1:0 --data "$data" --workers 1 \
    --max-particles 10000000 --max-memory-mb 16000 --max-seconds 0 >"$out" 2>/dev/null &
pid=$!
trap 'kill $pid 2>/dev/null; rm -f "$out"' EXIT
for _ in $(seq 100); do
    grep -q . "$out" && break
    sleep 0.1
done
base=$(grep -o 'http://[0-9.:]*' "$out" | head -1)
if [ -z "$job" ]; then
    config='seed = 1
[domain]
shape = "rectangle"
width = 2130
height = 2130
[grading]
uniform = [1.0, 2.0]
[output]
formats = ["csv"]
'
    job=$(curl -sf -X POST -H 'content-type: application/toml' --data-binary "$config" \
        "$base/api/v1/jobs?kind=pack" | sed -n 's/.*"id":"\([0-9a-f]*\)".*/\1/p')
    echo "job $job"
    for _ in $(seq 3600); do
        state=$(curl -sf "$base/api/v1/jobs/$job" | sed -n 's/.*"state":"\([a-z]*\)".*/\1/p')
        [ "$state" = succeeded ] && break
        case $state in failed|cancelled) echo "job $state"; exit 1;; esac
        sleep 1
    done
fi
particles=$(curl -sf "$base/api/v1/jobs/$job" | grep -o '"particles":[0-9]*' | head -1)
size=$(stat -c %s "$data/jobs/$job/packing.csv")
echo "job $job: $particles, packing.csv $size bytes"
kb() { awk -v k="$1" '$1 == k":" { print $2 }' "/proc/$pid/status"; }
for path in "files/packing.csv" "packing"; do
    sleep 2
    idle=$(kb VmRSS)
    echo 5 >"/proc/$pid/clear_refs"
    start=$(date +%s.%N)
    for _ in $(seq 10); do
        curl -s -o /dev/null -w '%{http_code} %{size_download}\n' "$base/api/v1/jobs/$job/$path" &
    done | sort | uniq -c
    end=$(date +%s.%N)
    peak=$(kb VmHWM)
    echo "$path: idle VmRSS $idle kB, peak VmHWM $peak kB, +$((peak - idle)) kB; ten downloads in $(echo "$end - $start" | bc) s"
done
