#!/usr/bin/env bash
# The speed benchmark of docs/performance.md, side by side in one run:
#   1. cargo bench --bench realtime: real-time factor, doStep mean/p99/worst, page faults and the
#      RMS force error against a converged run at each tolerance; one against six dampers;
#   2. the FMU against the plain-Python cross-check on the same input (damper-crosscheck);
#   3. the diagnosis of a 60 s, 1 kHz record (damper generate, then damper diagnose), timed.
# Writes out/benchmark/benchmark.md (and prints it) and its headline figures, out/benchmark/figures.json
# (damper_tools.benchmark_figures). About 3 minutes on 2 cores.
#
#   bash scripts/benchmark.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
out=out/benchmark
mkdir -p "$out"
report=$out/benchmark.md
{
    echo "# Benchmark, $(date -u +%Y-%m-%d) on $(nproc) cores: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | xargs)"
    echo "load average at the start: $(cut -d' ' -f1-3 /proc/loadavg)"
    echo
    echo "## 1. The damper in process (cargo bench --bench realtime)"
    echo
} >"$report"
cargo bench --bench realtime 2>/dev/null | tee -a "$report"
python3 scripts/package_fmu.py >/dev/null
{
    echo
    echo "## 2. FMU against the Python cross-check (damper-crosscheck --duration 1)"
    echo
} >>"$report"
.venv/bin/damper-crosscheck --duration 1 --out "$out/crosscheck" | tee -a "$report"
cargo build --release -p damper_cli 2>/dev/null
damper=target/release/damper
$damper generate --effect mount_compliance --seed 5 --duration 60 --minimal \
    --out "$out/rec60.csv" --truth "$out/rec60.truth.json" >/dev/null
start=$(date +%s.%N)
$damper diagnose "$out/rec60.csv" --load-cell-lowpass 400 --out "$out/diagnose60" >/dev/null
end=$(date +%s.%N)
{
    echo
    echo "## 3. Diagnosis of a 60 s, 1 kHz record (mount compliance hidden, seed 5), 2 threads"
    echo
    python3 - "$out/diagnose60/summary.json" "$start" "$end" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
runs = sum(c["model_runs"] for c in s["candidates"])
fitted = "; ".join(f"{k}={v['value']:.4e}" for c in s["candidates"][:1] for k, v in c["params"].items())
print(f"- wall time {float(sys.argv[3]) - float(sys.argv[2]):.1f} s, verdict {s['verdict']} ({s['best_effect']}), {fitted}")
print(f"- one model run {s['model_run_s']:.2f} s at rtol {s['floor']['rtol']:g}; {runs} runs for the {len(s['candidates'])} candidates' fits")
PY
} | tee -a "$report"
echo "report: $report"
# the headline figures, as docs/benchmark.json holds them (write them there with
# `.venv/bin/python -m damper_tools.benchmark_figures out/benchmark/benchmark.md --docs`)
.venv/bin/python -m damper_tools.benchmark_figures "$report" >"$out/figures.json"
echo "figures: $out/figures.json"
