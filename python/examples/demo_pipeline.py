#!/usr/bin/env python3
"""The demo's pipeline from Python: calibrate the camera from images, measure every target pose
from its image folder, identify the H4 (variant D), evaluate V1–V3, and plot with matplotlib.

The campaign is the one `mire demo` simulates (rendered images, encoder readings, straight-line
records). Give one with --campaign DIR (DIR/campaign of a `mire demo -o DIR` run), or let the
script run `mire demo --quick` to make one (--mire names the command if it is not on PATH).

    PYTHONPATH=build/python/module /usr/bin/python3 python/examples/demo_pipeline.py \
        --mire build/apps/mire -o /tmp/mire_python_demo
"""
import argparse
import pathlib
import subprocess
import time

import numpy as np

import mire

cal, met, mech = mire.calibration, mire.metrology, mire.mechanism


def make_campaign(mire_command, output):
    subprocess.run([mire_command, "demo", "--quick", "-o", str(output / "cli_demo")], check=True,
                   stdout=subprocess.DEVNULL)
    return output / "cli_demo" / "campaign"


def calibrate(campaign, target):
    images = sorted((campaign / "calibration" / "images").glob("*.png"))
    result = cal.calibrateFromImages(target, images)
    camera = result.camera
    print(f"camera: {camera.modelName()} from {result.used_views} of {len(images)} views, rms {camera.rms_px:.3f} px")
    for name, value, sigma in zip(camera.parameterNames(), camera.params, camera.sigmas()):
        print(f"  {name:3s} = {value:12.6f} ± {sigma:.6f}")
    return result


def measure(campaign, camera, target):
    options = met.MeasurementOptions()
    options.integrity.split = met.SplitPolicy.KeepLargest  # a simulated robot is static
    measured = []
    for folder in sorted(p for p in (campaign / "poses").iterdir() if p.is_dir()):
        m = met.measurePoseFromFolder(camera, target, folder, options)
        if not m.ok:
            print(f"pose {folder.name}: {m.error}")
            continue
        measured.append(met.MeasuredPose(folder.name, m.features.images_used,
                                         len(met.listPoseImages(folder)), m.estimate, m.flags))
    sigmas = np.array([p.estimate.sigmas for p in measured])
    print(f"measured {len(measured)} poses; median σ {1e3 * np.median(sigmas[:, :3]):.3f} mm, "
          f"{np.degrees(np.median(sigmas[:, 3:])):.4f} deg")
    return measured


def identify(measured, joints_csv, lines_csv):
    by_id = {row.pose_id: row.joints for row in mech.readJointsCsv(joints_csv)}
    ids = [p.pose_id for p in measured]
    poses = mech.observationsFromArrays(
        ids,
        np.array([np.concatenate([p.estimate.translation, p.estimate.rotation_vector]) for p in measured]),
        np.array([by_id[i] for i in ids]),
        np.array([p.estimate.covariance for p in measured]))
    nominal = mech.H4Nominal()
    initial = mech.makeH4VariantModel("D", nominal, poses)
    result = mech.identify(initial, poses)
    lines = [np.array(line.joints) for line in mech.readLinesCsv(lines_csv)]
    before = mech.jointResidualCriteria(initial, poses)
    after = mech.jointResidualCriteria(result.model, poses)
    v3_before = mech.straightnessCriterion(initial.mechanism, initial.geometricValues(), lines)
    v3_after = mech.straightnessCriterion(result.model.mechanism, result.model.geometricValues(), lines)
    print(f"identified {len(result.free_names)} parameters, condition number "
          f"{result.identifiability.condition_number:.3g}")
    print(f"V2 {np.degrees(before.v2_rad):.4f} -> {np.degrees(after.v2_rad):.4f} deg; "
          f"V3 {1e3 * v3_before.v3_m:.4f} -> {1e3 * v3_after.v3_m:.4f} mm")
    return initial, result, poses, (v3_before, v3_after)


def plot(calibration, measured, initial, result, poses, straightness, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(2, 2, figsize=(12, 9))
    residuals = np.concatenate([v.residuals for v in calibration.views if v.used])
    axes[0, 0].scatter(residuals[:, 0], residuals[:, 1], s=2, alpha=0.4)
    axes[0, 0].set(title=f"calibration residuals (rms {calibration.camera.rms_px:.3f} px)", xlabel="u (px)",
                   ylabel="v (px)", aspect="equal")
    sigmas = np.array([p.estimate.sigmas for p in measured])
    axes[0, 1].plot(1e3 * sigmas[:, :3], ".", label=["σ tx", "σ ty", "σ tz"])
    axes[0, 1].set(title="pose precision (total σ)", xlabel="pose", ylabel="mm")
    axes[0, 1].legend()
    q_before = np.array([p.joints - initial.predictJoints(p.cTm).joints for p in poses])
    q_after = np.array([r.residual for r in result.poses])
    axes[1, 0].plot(np.degrees(q_before).ravel(), ".", ms=3, label="nominal")
    axes[1, 0].plot(np.degrees(q_after).ravel(), ".", ms=3, label="identified")
    axes[1, 0].set(title="joint residuals q̄ − f (all joints of all poses)", xlabel="residual index", ylabel="deg")
    axes[1, 0].legend()
    before, after = straightness
    for points, label in ((before.points[0], "nominal"), (after.points[0], "identified")):
        centred = points - points.mean(axis=0)
        direction = np.linalg.svd(centred)[2][0]
        deviation = centred - np.outer(centred @ direction, direction)
        axes[1, 1].plot(centred @ direction * 1e3, np.linalg.norm(deviation, axis=1) * 1e3, ".-", label=label)
    axes[1, 1].set(title=f"line 1 rebuilt by the FKM: V3 {1e3 * before.v3_m:.3f} → {1e3 * after.v3_m:.3f} mm",
                   xlabel="along the line (mm)", ylabel="distance to the fitted line (mm)")
    axes[1, 1].legend()
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    print(f"wrote {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--campaign", type=pathlib.Path, help="campaign folder of a `mire demo` run")
    parser.add_argument("--mire", default="mire", help="the mire command (to simulate a campaign)")
    parser.add_argument("-o", "--output", type=pathlib.Path, default=pathlib.Path("mire_python_demo"))
    args = parser.parse_args()
    args.output.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    campaign = args.campaign or make_campaign(args.mire, args.output)
    target = met.Target.fromFile(campaign / "target.yaml")
    calibration = calibrate(campaign, target)
    cal.writeCamera(calibration.camera, args.output / "camera.yaml")
    measured = measure(campaign, calibration.camera, target)
    met.writePosesCsv(args.output / "poses.csv", measured)
    met.writePosesCovarianceCsv(args.output / "poses_covariance.csv", measured)
    initial, result, poses, straightness = identify(measured, campaign / "joints.csv", campaign / "lines.csv")
    mech.writeParameterFile(args.output / "identified_D.yaml", result.model.parameters, result.sigma,
                            [("model", "h4-12"), ("variant", "D")], "identified by python/examples/demo_pipeline.py")
    plot(calibration, measured, initial, result, poses, straightness, args.output / "demo_pipeline.png")
    print(f"done in {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
