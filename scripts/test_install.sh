#!/usr/bin/env bash
# The installed package, as a user gets it (doc/install.md): `cmake --install` the build into a
# temporary prefix, move the prefix (nothing may point back into the checkout or the build), run
# the installed `mire demo --quick`, build examples/ against the installed package with
# find_package(mire), run the three examples on the demo's images and check their numbers against
# the simulation's truth. Run by ctest (label `install`).
#   scripts/test_install.sh BUILD_DIR [--werror]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:?usage: test_install.sh BUILD_DIR [--werror]}" && pwd)"
flags=""
[ "${2:-}" = "--werror" ] && flags="-Wall -Wextra -Werror"
work="$(mktemp -d "${TMPDIR:-/tmp}/mire-install-test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
unset MIRE_DATA_DIR
step() { echo "test_install: $*"; }

step "install into $work/staging, then move it to $work/prefix"
cmake --install "$build" --prefix "$work/staging" >/dev/null
mv "$work/staging" "$work/prefix"
prefix="$work/prefix"
# Constant data only: the debug information names the sources, which is fine.
objcopy -O binary --only-section=.rodata "$prefix/bin/mire" "$work/rodata.bin"
if strings "$work/rodata.bin" | grep -F -q -e "$root" -e "$build"; then
  echo "test_install: the installed mire names a checkout or build path" >&2
  exit 1
fi

step "installed mire demo --quick"
cd "$work"
"$prefix/bin/mire" demo --quick -o "$work/demo" >"$work/demo.log" 2>&1 || { cat "$work/demo.log" >&2; exit 1; }
campaign="$work/demo/campaign"

step "build examples/ against the installed package"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$root/examples" -B "$work/examples" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_CXX_FLAGS="$flags" "${launcher[@]}" >"$work/examples.log" 2>&1 || { cat "$work/examples.log" >&2; exit 1; }
cmake --build "$work/examples" >>"$work/examples.log" 2>&1 || { cat "$work/examples.log" >&2; exit 1; }

step "pkg-config"
PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs mire | grep -q -- "-I$prefix/lib/pkgconfig/../../include"

step "run the examples"
ex="$work/examples"
"$ex/calibrate_folder" "$campaign/target.yaml" "$campaign/calibration/images" "$work/camera.yaml" >"$work/calibrate.txt" 2>/dev/null
"$ex/measure_poses" "$work/camera.yaml" "$campaign/target.yaml" "$campaign/poses" "$work/poses.csv" >"$work/measure.txt" 2>/dev/null
"$ex/identify_robot" "$work/poses.csv" "$campaign/joints.csv" >"$work/identify.txt"
cat "$work/calibrate.txt" "$work/identify.txt"
tail -1 "$work/measure.txt"

step "check against the simulation's truth"
python3 - "$work" "$campaign/truth" <<'PY'
import csv, math, re, sys, yaml
work, truth = sys.argv[1], sys.argv[2]
failures = []
def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok: failures.append(what)

# calibrate_folder: fx fy cx cy within 1 px and 4 sigma of the true camera, rms below 0.2 px.
cam = yaml.safe_load(open(f"{truth}/camera.yaml").read().replace("!!opencv-matrix", ""))
k = cam["camera_matrix"]["data"]
true = {"fx": k[0], "fy": k[4], "cx": k[2], "cy": k[5]}
text = open(f"{work}/calibrate.txt").read()
rms = float(re.search(r"rms ([0-9.]+) px", text).group(1))
check(rms < 0.2, f"calibration rms {rms} px < 0.2")
for name, value in true.items():
    est, sigma = map(float, re.search(rf"^{name}\s+(\S+)\s+sigma (\S+)", text, re.M).groups())
    check(abs(est - value) < min(1.0, 4 * sigma + 0.05), f"{name} {est:.3f} +- {sigma:.3f} vs truth {value:.3f}")

# measure_poses: at least 75 of the 81 poses, translation error rms under 1 mm (sigma ~0.25 mm).
truth_t = {r["pose_id"]: [float(r[c]) for c in ("tx_m", "ty_m", "tz_m")] for r in csv.DictReader(open(f"{truth}/poses_truth.csv"))}
rows = list(csv.DictReader(open(f"{work}/poses.csv")))
check(len(rows) >= 75, f"{len(rows)} poses measured (>= 75)")
err2 = [sum((float(r[c]) - t) ** 2 for c, t in zip(("tx_m", "ty_m", "tz_m"), truth_t[r["pose_id"]])) for r in rows]
rms_mm = 1e3 * math.sqrt(sum(err2) / (3 * len(err2)))
check(rms_mm < 1.0, f"pose translation error rms {rms_mm:.3f} mm < 1 mm")

# identify_robot: converged, joint residual cut by 3 at least, target mounting (mTe) recovered.
text = open(f"{work}/identify.txt").read()
nominal, identified = map(float, re.search(r"rms (\S+) rad \(nominal\) -> (\S+) rad", text).groups())
check("converged" in text and identified < nominal / 3, f"joint residual {nominal} -> {identified} rad, converged")
mte = yaml.safe_load(open(f"{truth}/robot.yaml"))["mTe"]
value = lambda name: float(re.search(rf"^{name}\s+(\S+)", text, re.M).group(1))
check(abs(value("x_ME") - 1e3 * mte[3]) < 1.5, f"x_ME {value('x_ME')} mm vs truth {1e3 * mte[3]:.3f}")
check(abs(value("y_ME") - 1e3 * mte[7]) < 1.5, f"y_ME {value('y_ME')} mm vs truth {1e3 * mte[7]:.3f}")
psi = math.degrees(math.atan2(mte[4], mte[0]))
check(abs(value("psi_ME") - psi) < 0.2, f"psi_ME {value('psi_ME')} deg vs truth {psi:.3f}")
sys.exit(1 if failures else 0)
PY
step "passed"
