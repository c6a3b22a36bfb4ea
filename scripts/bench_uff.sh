#!/usr/bin/env bash
# Benchmark of the UFF reader, whole process, side by side with pyuff.
#
# Generates a campaign (default 256 channels x 6400 lines, complex single:
# ASCII ~43 MB and its 58b twin ~13 MB) with our writer, then for each file:
#  - ours: `frfup info FILE` (release; the streaming reader), best of RUNS
#    runs (page cache warm): MB/s on wall time and on CPU time (user+sys, from
#    wait4 rusage), and peak RSS (ru_maxrss) as a multiple of the decoded
#    bytes: the values as held in memory (58b single precision is kept as
#    f32, 8 bytes per complex point; ASCII values are f64, 16 bytes), as
#    `read_uff` counts them. Also the fixed cost: peak RSS of the same command
#    on a one-record file of the same kind (code and libraries; measured
#    with /usr/bin/time, since a child of Python starts with Python's RSS).
#  - pyuff: `pyuff.UFF(path).read_sets()`, one run, bounded by PYUFF_TIMEOUT
#    seconds (default 300), wall and CPU;
#  - the ratios ours/pyuff.
# Wall times are noisy when other builds share the cores: compare CPU MB/s.
#
# Usage: scripts/bench_uff.sh [channels] [lines]
# Env: RUNS (default 7), PYUFF_TIMEOUT (default 300), BENCH_UFF_DIR,
#      BENCH_UFF_CMD=example to time parsers/examples/read_uff instead,
#      FRFUP_BIN=PATH to time that frfup binary (e.g. a copy built before a
#      change) instead of building one; CARGO_TARGET_DIR is honoured.
set -euo pipefail
channels=${1:-256}
lines=${2:-6400}
runs=${RUNS:-7}
root=$(cd "$(dirname "$0")/.." && pwd)
target=${CARGO_TARGET_DIR:-$root/target}
dir=${BENCH_UFF_DIR:-$target/bench_uff}
mkdir -p "$dir"
cd "$root"
cargo build --release -p frfup-parsers --features bench --example gen_campaign --example read_uff --quiet
if [[ -n ${FRFUP_BIN:-} ]]; then
    cmd=("$(realpath "$FRFUP_BIN")" info)
elif [[ ${BENCH_UFF_CMD:-frfup} == frfup ]]; then
    cargo build --release --bin frfup --quiet
    cmd=("$target/release/frfup" info)
else
    cmd=("$target/release/examples/read_uff")
fi
ascii=$dir/campaign_${channels}x${lines}_ascii.uff
binary=$dir/campaign_${channels}x${lines}_58b.uff
if [[ ! -s $ascii || ! -s $binary ]]; then
    "$target"/release/examples/gen_campaign "$ascii" "$binary" "$channels" "$lines"
fi
tiny_ascii=$dir/tiny_ascii.uff
tiny_binary=$dir/tiny_58b.uff
if [[ ! -s $tiny_ascii || ! -s $tiny_binary ]]; then
    "$target"/release/examples/gen_campaign "$tiny_ascii" "$tiny_binary" 1 16 > /dev/null
fi
python3 -c "import pyuff" 2>/dev/null || python3 -m pip install --quiet pyuff || true

echo "cores: $(nproc); load: $(cut -d' ' -f1-3 /proc/loadavg); command: ${cmd[*]} FILE"
python3 - "$runs" "${PYUFF_TIMEOUT:-300}" "$ascii" "$binary" "$tiny_ascii" "$tiny_binary" "$target/release/examples/read_uff" "${cmd[@]}" <<'PY'
import os, re, subprocess, sys, time

runs, pyuff_timeout = int(sys.argv[1]), float(sys.argv[2])
files = {"ascii": sys.argv[3], "58b": sys.argv[4]}
tiny = {"ascii": sys.argv[5], "58b": sys.argv[6]}
reader = sys.argv[7]  # prints the decoded bytes
cmd = sys.argv[8:]

def measured(argv, timeout=None):
    """Whole process: spawn to exit, wall and CPU (user + sys) and peak RSS.
    Without a timeout the parent blocks in wait4 (no polling delay); with one
    it polls every 0.5 ms (pyuff runs for seconds)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    actions = [(os.POSIX_SPAWN_DUP2, devnull, 1), (os.POSIX_SPAWN_DUP2, devnull, 2)]
    t = time.perf_counter()
    pid = os.posix_spawnp(argv[0], argv, os.environ, file_actions=actions)
    if timeout is None:
        _, status, ru = os.wait4(pid, 0)
    else:
        deadline = t + timeout
        while True:
            wpid, status, ru = os.wait4(pid, os.WNOHANG)
            if wpid == pid:
                break
            if time.perf_counter() > deadline:
                os.kill(pid, 9)
                os.wait4(pid, 0)
                os.close(devnull)
                return None
            time.sleep(0.0005)
    wall = time.perf_counter() - t
    os.close(devnull)
    return wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss, os.waitstatus_to_exitcode(status)

def decoded_bytes(path):
    out = subprocess.run([reader, path], capture_output=True, text=True).stdout
    m = re.search(r"decoded ([0-9.]+) MB", out)
    return float(m.group(1)) * 1e6 if m else float("nan")

def fixed_rss_kb(path):
    """Peak RSS (kB) of the command on a one-record file, via /usr/bin/time."""
    r = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd + [path],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        return float(r.stderr.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return float("nan")

PYUFF = "import sys, pyuff; pyuff.UFF(sys.argv[1]).read_sets()"
rows = []
for kind, path in files.items():
    mb = os.path.getsize(path) / 1e6
    decoded = decoded_bytes(path)
    best_wall = best_cpu = float("inf")
    rss = 0
    for _ in range(runs):
        r = measured(cmd + [path])
        if r is None or r[3] != 0:
            sys.exit(f"{kind}: {' '.join(cmd)} {path} failed")
        best_wall, best_cpu = min(best_wall, r[0]), min(best_cpu, r[1])
        rss = max(rss, r[2])
    fixed = fixed_rss_kb(tiny[kind])
    py = measured([sys.executable, "-c", PYUFF, path], timeout=pyuff_timeout)
    if py is None or py[3] != 0:
        py_wall = py_cpu = float("nan")
        py_note = f"(timeout {pyuff_timeout:.0f} s or failed)"
    else:
        py_wall, py_cpu, py_note = py[0], py[1], ""
    ours_w, ours_c = mb / best_wall, mb / best_cpu
    py_w, py_c = mb / py_wall, mb / py_cpu
    print(
        f"{kind:5s} {mb:6.1f} MB: ours {ours_w:7.0f} MB/s wall, {ours_c:7.0f} MB/s CPU "
        f"(best of {runs}: {best_wall * 1e3:.1f} ms wall, {best_cpu * 1e3:.1f} ms CPU); "
        f"pyuff {py_w:5.1f} MB/s wall, {py_c:5.1f} MB/s CPU {py_note}; "
        f"ratio {ours_w / py_w:5.0f}x wall, {ours_c / py_c:5.0f}x CPU; "
        f"peak RSS {rss * 1024 / 1e6:.1f} MB = {rss * 1024 / decoded:.2f}x decoded ({decoded / 1e6:.1f} MB); "
        f"fixed cost {fixed * 1024 / 1e6:.1f} MB, beyond it {(rss - fixed) * 1024 / decoded:.2f}x decoded"
    )
PY
