#!/usr/bin/env bash
# Peer benchmark: Pinocchio (C++, from PyPI) and robid's compiled models, timed back to back
# on this machine, in alternating rounds, with each side's own trigonometric baseline.
# Optional: CI never runs it (docs/performance.md#measured-in-the-same-run).
#
#   bash benches/peers/run.sh
#
# What it does:
#   1. Pinocchio: a Python virtual environment under /tmp (never in the repository) with
#      `pin` and the cmeel wheels it needs to compile against (Eigen and urdfdom headers);
#      the wheels ship Pinocchio's C++ headers and shared libraries under cmeel.prefix.
#   2. Compiles pinocchio_bench.cpp with g++ -O3 for the default x86-64 target, the same
#      target as robid's release build, two ways: with the algorithms instantiated from
#      Pinocchio's headers in the program (`default-headers`, the figure reported), and
#      calling the wheel's precompiled instances (`default-library`). No -march=native
#      build: against the wheel's libraries (built for the baseline target) it crashes
#      (docs/performance.md#measured-in-the-same-run).
#   3. Builds `robid` in release.
#   4. Runs, PEERS_ROUNDS times (3), alternating which side goes first: `robid bench
#      --robot ur5e --json`, the Pinocchio bench on the UR5 URDF, `robid bench --robot
#      panda --json`, the Pinocchio bench on the Panda URDF with the two finger joints
#      locked (the 7-joint arm, as robid's reference Panda).
#   5. Prints a table: medians over the rounds of each side's nanoseconds, and the median
#      of the per-round ratios Pinocchio / robid.
#
# Environment: PEERS_VENV (default /tmp/pinenv), PEERS_BUILD (default /tmp/robid-peers:
# the compiled bench and the raw JSON lines), PEERS_ROUNDS (default 3), PEERS_VARIANTS
# (default "default library": which of the two builds to time),
# CARGO_TARGET_DIR as for cargo.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="${PEERS_VENV:-/tmp/pinenv}"
build="${PEERS_BUILD:-/tmp/robid-peers}"
rounds="${PEERS_ROUNDS:-3}"
variants="${PEERS_VARIANTS:-default library}"
ur5_urdf="$root/data/example_robot_data/ur5/ur5_robot.urdf"
panda_urdf="$root/data/example_robot_data/panda/panda.urdf"
panda_locked=(panda_finger_joint1 panda_finger_joint2)
mkdir -p "$build"

echo "== Pinocchio in $venv" >&2
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
# pin: the library; cmeel-eigen and cmeel-urdfdom-headers: headers pin's own wheels need
# only to compile against it (build dependencies, not installed with pin).
# (one `pip show` per package: given several, it succeeds when any one is installed)
for package in pin cmeel-eigen cmeel-urdfdom-headers; do
  if ! "$venv/bin/pip" show "$package" > /dev/null 2>&1; then
    "$venv/bin/pip" install --quiet pin cmeel-eigen cmeel-urdfdom-headers
    break
  fi
done
prefix="$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/cmeel.prefix"
pin_version="$("$venv/bin/pip" show pin | sed -n 's/^Version: //p')"
[ -f "$prefix/include/pinocchio/algorithm/rnea.hpp" ] || {
  echo "no Pinocchio headers under $prefix" >&2
  exit 1
}

if ! command -v g++ > /dev/null; then
  echo "g++ is missing: apt-get install g++" >&2
  exit 1
fi

# The compile definitions of the wheel's CMake targets (pinocchioTargets.cmake).
cxxflags=(-std=c++17 -O3 -DNDEBUG
  -I"$prefix/include" -I"$prefix/include/eigen3" -I"$prefix/include/urdfdom_headers"
  -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30
  -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12)
ldflags=(-L"$prefix/lib" -Wl,-rpath,"$prefix/lib"
  -lpinocchio_parsers -lpinocchio_default -lurdfdom_model -lconsole_bridge)
for v in $variants; do
  bin="$build/pinocchio_bench-$v"
  case "$v" in
    default) extra=() ;;
    library) extra=(-DPINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION) ;;
    *) echo "unknown variant $v" >&2; exit 2 ;;
  esac
  # About a minute of CPU each: rebuilt only when the source or the wheel changed.
  if [ ! -x "$bin" ] || [ "$here/pinocchio_bench.cpp" -nt "$bin" ] \
    || [ "$prefix/lib/libpinocchio_default.so" -nt "$bin" ]; then
    echo "== g++ ${extra[*]} -> $bin" >&2
    g++ "${cxxflags[@]}" "${extra[@]}" "$here/pinocchio_bench.cpp" "${ldflags[@]}" -o "$bin"
  fi
done

echo "== cargo build --release --bin robid" >&2
(cd "$root" && cargo build --release --quiet -p robots --bin robid)
robid="${CARGO_TARGET_DIR:-$root/target}/release/robid"

raw="$build/results-$(date -u +%Y%m%dT%H%M%SZ).jsonl"
load_before="$(cut -d' ' -f1-3 /proc/loadavg)"
pinocchio() { # URDF LABEL [LOCKED...]
  for v in $variants; do "$build/pinocchio_bench-$v" "$@"; done
}
robid_side() { "$robid" bench --robot "$1" --json; }
for ((r = 0; r < rounds; r++)); do
  echo "== round $((r + 1)) of $rounds" >&2
  if ((r % 2 == 0)); then
    robid_side ur5e | sed "s/^{/{\"side\":\"robid\",\"round\":$r,/" >> "$raw"
    pinocchio "$ur5_urdf" ur5e | sed "s/^{/{\"side\":\"pinocchio\",\"round\":$r,/" >> "$raw"
    robid_side panda | sed "s/^{/{\"side\":\"robid\",\"round\":$r,/" >> "$raw"
    pinocchio "$panda_urdf" panda "${panda_locked[@]}" \
      | sed "s/^{/{\"side\":\"pinocchio\",\"round\":$r,/" >> "$raw"
  else
    pinocchio "$ur5_urdf" ur5e | sed "s/^{/{\"side\":\"pinocchio\",\"round\":$r,/" >> "$raw"
    robid_side ur5e | sed "s/^{/{\"side\":\"robid\",\"round\":$r,/" >> "$raw"
    pinocchio "$panda_urdf" panda "${panda_locked[@]}" \
      | sed "s/^{/{\"side\":\"pinocchio\",\"round\":$r,/" >> "$raw"
    robid_side panda | sed "s/^{/{\"side\":\"robid\",\"round\":$r,/" >> "$raw"
  fi
done
load_after="$(cut -d' ' -f1-3 /proc/loadavg)"

cpu="$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)"
echo "raw JSON lines: $raw" >&2
"$venv/bin/python" - "$raw" "$pin_version" "$cpu" "$(nproc)" "$load_before" "$load_after" <<'EOF'
import json, statistics, sys

raw, pin_version, cpu, cores, load_before, load_after = sys.argv[1:]
rows = [json.loads(line) for line in open(raw)]
med = statistics.median
# robid program -> Pinocchio function computing the comparable quantity.
pairs = [
    ("inverse_dynamics", "rnea", "inverse dynamics"),
    ("mass_matrix", "crba", "mass matrix (upper triangle)"),
    ("mass_matrix", "crba_symmetric", "mass matrix (crba + symmetrised)"),
    ("gravity", "computeGeneralizedGravity", "gravity"),
    ("coriolis", "nonLinearEffects", "Coriolis (nonlinear effects)"),
]
robots = []
for r in rows:
    if r["robot"] not in robots:
        robots.append(r["robot"])
variants = []
for r in rows:
    if r["side"] == "pinocchio" and r["variant"] not in variants:
        variants.append(r["variant"])
rounds = sorted({r["round"] for r in rows})

def get(side, robot, rnd, variant=None):
    for r in rows:
        if (r["side"], r["robot"], r["round"]) == (side, robot, rnd) and (
            variant is None or r.get("variant") == variant
        ):
            return r
    raise KeyError((side, robot, rnd, variant))

print(f"Pinocchio {pin_version} (g++ -O3, default x86-64 target) vs robid bench, "
      f"{len(rounds)} alternating rounds; {cpu}, {cores} cores; "
      f"load average {load_before} before, {load_after} after")
print("ns: median over the rounds of each program's median; ratio: median over the rounds "
      "of Pinocchio / robid in the same round; trig: each side's baseline in that process")
for variant in variants:
    print()
    print(f"Pinocchio build: {variant}")
    print("| robot | program | robid ns | Pinocchio ns | Pinocchio / robid "
          "| robid / its 6 x trig | Pinocchio / its n x trig |")
    print("|---|---|---|---|---|---|---|")
    for robot in robots:
        for mine, theirs, label in pairs:
            ours = [get("robid", robot, k)["programs"][mine] for k in rounds]
            peer = [get("pinocchio", robot, k, variant)["programs"][theirs] for k in rounds]
            ratio = [p / o for p, o in zip(peer, ours)]
            own_trig = [get("robid", robot, k)["programs"][mine]
                        / get("robid", robot, k)["baseline_trig_ns"] for k in rounds]
            peer_trig = [get("pinocchio", robot, k, variant)["programs"][theirs]
                         / get("pinocchio", robot, k, variant)["baseline_trig_ns"]
                         for k in rounds]
            print(f"| {robot} | {label} | {med(ours):.1f} | {med(peer):.1f} | "
                  f"{med(ratio):.2f} | {med(own_trig):.2f} | {med(peer_trig):.2f} |")
print()
print("Trigonometric baselines, ns (medians over the rounds). robid's: 6 x (sin + cos) through "
      "the Rust libm crate, which robid's generated code calls; Pinocchio's process: glibc")
print("| robot | robid: 6 x libm-crate (sin + cos) | glibc: 6 x (sin + cos), robid's values "
      "| glibc: 6 x sincos, robid's values | glibc: n x (sin + cos), random states |")
print("|---|---|---|---|---|")
variant = variants[0]
for robot in robots:
    b = med([get("robid", robot, k)["baseline_trig_ns"] for k in rounds])
    p6 = med([get("pinocchio", robot, k, variant)["baseline_trig6_ns"] for k in rounds])
    s6 = med([get("pinocchio", robot, k, variant)["baseline_sincos6_ns"] for k in rounds])
    pn = med([get("pinocchio", robot, k, variant)["baseline_trig_ns"] for k in rounds])
    n = get("pinocchio", robot, rounds[0], variant)["nq"]
    print(f"| {robot} | {b:.1f} | {p6:.1f} | {s6:.1f} | {pn:.1f} (n = {n}) |")
print()
print("ur5e: robid's UR5e (DH) model against the UR5 URDF (same structure, 6 revolute "
      "joints; other lengths and inertias). panda: the 7-joint arm on both sides "
      "(Pinocchio: finger joints locked).")
EOF
