#!/usr/bin/env bash
# Builds the Cortex-M4F firmware (embedded/firmware), runs it in QEMU
# (mps2-an386, semihosting), compares its report lines with the x86-64
# reference and prints, last, one line
#   firmware: flash=<bytes> ram=<bytes> stack=<bytes> f32_err=<rel> checks=ok
# (f32_err: largest position error of Evaluator::eval_f32 against eval on
# the demo grid, relative to the diagonal, as the firmware measured it)
# (checks=FAIL and exit status 1 on any mismatch).
#
#   scripts/firmware.sh [--smooth] [--expect FILE] [--target-dir DIR] [--timeout SECONDS]
#
# --smooth         the evaluate-and-tessellate firmware (feature
#                  `smooth-only`: the pyramid's build, evaluation, depths
#                  and tessellation, no creased cube, no voxels) with only
#                  the eigen tables of the pyramid's valences baked
#                  (CCSS_TABLE_VALENCES=3,4); the host reference runs with
#                  `--smooth` too.
# --valences LIST  the valences whose eigen tables are baked
#                  (CCSS_TABLE_VALENCES, e.g. 3-8 or 3,4; default 3-8, with
#                  --smooth 3,4).
# --expect FILE    the reference lines (tests/tests/firmware.rs computes them
#                  in its own process); without it the script runs
#                  `cargo run --release -p ccss-embedded-demo --example host`.
# --target-dir DIR cargo target directory of the thumb build (default
#                  target/firmware under the repository).
# --timeout S      QEMU wall-clock limit (default 300).
#
# flash = .vector_table + .text + .rodata (+ .data initial values, printed
# apart); ram = .data + .bss; stack = deepest stack of any phase, measured
# by stack painting; ins = QEMU instruction counts (-icount shift=0: one
# virtual nanosecond per instruction, read from SysTick). Needs
# qemu-system-arm, python3, the thumbv7em-none-eabihf target and `size`.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
expect=""
target="$root/target/firmware"
limit=300
features=()
host_args=()
valences=3-8
valences_given=""
while [ $# -gt 0 ]; do
  case "$1" in
    --smooth) features=(--features smooth-only); host_args=(--smooth)
      valences=3,4; shift ;;
    --valences) valences_given="$2"; shift 2 ;;
    --expect) expect="$2"; shift 2 ;;
    --target-dir) target="$2"; shift 2 ;;
    --timeout) limit="$2"; shift 2 ;;
    *) echo "firmware.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -n "$valences_given" ] && valences="$valences_given"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "firmware.sh: $*" >&2; echo "firmware: flash=0 ram=0 stack=0 f32_err=n/a checks=FAIL"; exit 1; }

command -v qemu-system-arm >/dev/null || fail "qemu-system-arm not found (Debian: apt-get install qemu-system-arm)"
(cd "$root/embedded/firmware" && CARGO_TARGET_DIR="$target" CCSS_TABLE_VALENCES="$valences" "${CARGO:-cargo}" build --release --quiet "${features[@]}") \
  || fail "firmware build failed"
elf="$target/thumbv7em-none-eabihf/release/ccss-firmware"

if [ -z "$expect" ]; then
  expect="$work/host.txt"
  (cd "$root" && "${CARGO:-cargo}" run --release --quiet -p ccss-embedded-demo --example host -- "${host_args[@]}") >"$expect" \
    || fail "host reference failed"
fi

start=$(date +%s)
status=0
timeout "$limit" qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic \
  -icount shift=0 -semihosting-config enable=on,target=native -kernel "$elf" \
  >"$work/qemu.txt" 2>&1 </dev/null || status=$?
echo "qemu: exit $status after $(( $(date +%s) - start )) s"
cat "$work/qemu.txt"
[ "$status" = 0 ] || fail "firmware run failed (exit $status; 124 = timeout)"

size -A "$elf" >"$work/size.txt"
# The baked eigen tables' share of .rodata (0 with runtime tables).
tables=$( (nm -S "$elf" 2>/dev/null || true) | awk '/BAKED_TABLES/ { print $2; exit }')
echo "baked tables in flash: $((16#${tables:-0})) bytes (CCSS_TABLE_VALENCES=$valences)"
python3 - "$expect" "$work/qemu.txt" "$work/size.txt" <<'PY'
import struct, sys

def lines(path):
    out = {}
    for l in open(path):
        w = l.split()
        if len(w) >= 3 and w[1] in ("int", "f64"):
            out[w[0]] = w[1:]
    return out

def f(bits):
    return struct.unpack("<d", struct.pack("<Q", int(bits, 16)))[0]

host, fw = lines(sys.argv[1]), lines(sys.argv[2])
bad = []
worst = 0.0
for key, h in host.items():
    m = fw.get(key)
    if m is None:
        bad.append(f"{key}: missing in the firmware output")
    elif h[0] == "int":
        if m != h:
            bad.append(f"{key}: firmware {m[1]} host {h[1]}")
    else:
        hs, ha, hc = f(h[1]), f(h[2]), h[3]
        ms, ma, mc = f(m[1]), f(m[2]), m[3]
        if key == "f32.max_err":
            # A difference of nearly equal f32 and f64 values, relative to
            # the diagonal: the last bits of the f64 side move it by
            # 1e-16 absolute, so compare it absolutely.
            if hc != mc or not abs(hs - ms) <= 1e-12:
                bad.append(f"{key}: {ms:.6e} vs {hs:.6e}")
            continue
        scale = max(ha, ma, 1e-300)
        err = max(abs(hs - ms), abs(ha - ma)) / scale
        worst = max(worst, err)
        if hc != mc or not err <= 1e-12:
            bad.append(f"{key}: relative difference {err:.3e} (counts {mc} vs {hc})")
extra = set(fw) - set(host)
if extra:
    bad.append("firmware lines the host does not have: " + " ".join(sorted(extra)))
if not host:
    bad.append("no reference lines")
sec = {}
for l in open(sys.argv[3]):
    w = l.split()
    if len(w) >= 2 and w[0].startswith(".") and w[1].isdigit():
        sec[w[0]] = int(w[1])
flash = sec.get(".vector_table", 0) + sec.get(".text", 0) + sec.get(".rodata", 0)
ram = sec.get(".data", 0) + sec.get(".bss", 0)
f32_err = "n/a"
if "f32.max_err" in fw:
    f32_err = f"{f(fw['f32.max_err'][1]):.2e}"
stack, done = 0, False
for l in open(sys.argv[2]):
    w = l.split()
    if len(w) == 3 and w[0] == "stack":
        stack = max(stack, int(w[2]))
    done |= l.strip() == "done"
if not done:
    bad.append("the firmware did not finish")
for b in bad:
    print("mismatch:", b, file=sys.stderr)
print(f"compared {len(host)} lines, largest relative difference of the f64 checksums {worst:.3e}")
print(f"sections: .text {sec.get('.text', 0)} .rodata {sec.get('.rodata', 0)} .data {sec.get('.data', 0)} .bss {sec.get('.bss', 0)}")
print(f"firmware: flash={flash} ram={ram} stack={stack} f32_err={f32_err} checks={'FAIL' if bad else 'ok'}")
sys.exit(1 if bad else 0)
PY
