"""The bad-input matrix of the Python module (doc/robustness.md), the same shape as the CLI's
(tests/apps/bad_input_cases.cpp): one case per row, each with the exception it must raise, the
fragments its message must hold, and a check that every input file kept its bytes. A reader
that blocked on a FIFO or on /dev/zero would hang: every case runs under a 10 s alarm, so a
regression fails instead of hanging the suite."""
import os
import signal
import subprocess

import numpy as np
import pytest

import mire
from test_mechanisms import Robot

mech = mire.mechanism
met = mire.metrology
cal = mire.calibration

ALARM_S = 10


def fifo(folder, name="pipe"):
    path = folder / name
    os.mkfifo(path)
    return path


def chessboard_spec(cols, rows):
    spec = met.TargetSpec()
    spec.type, spec.cols, spec.rows, spec.square_size_m = met.TargetType.Chessboard, cols, rows, 0.02
    return spec


def small_target():
    return met.Target(chessboard_spec(6, 5))


def camera():
    return cal.Camera(480, 360, [420.0, 420.0, 239.5, 179.5, -0.1, 0.02, 0.0, 0.0, 0.0])


def h4_observations():
    ids, cTm, joints, covariance = Robot().observe(Robot.protocol(), np.random.default_rng(5))
    return mech.observationsFromArrays(ids, cTm, joints, covariance)


def monte_carlo(threads):
    poses = h4_observations()
    model = mech.makeH4VariantModel("D", mech.H4Nominal(), poses)
    options = mech.MonteCarloOptions()
    options.subset_sizes, options.repeats, options.threads = [40], 1, threads
    return mech.runMonteCarloStudy(model, poses, [], options)


def design_information():
    model = mech.makeDesignModel("h4-12")
    w = mech.Workspace()
    w.x, w.y, w.z = mech.Interval(-0.1, 0.1), mech.Interval(-0.1, 0.1), mech.Interval(-0.70, -0.55)
    w.rotations = [mech.Interval(-0.3, 0.3)]
    poses = mech.generateCandidatePoses(model.registered.mechanism, model.registered.nominal.values(), w, 200, 1)
    return mech.candidateInformation(model, mech.defaultMountingGuess(w), poses, mech.DesignOptions())


def set_camera_covariance(size):
    c = camera()
    c.covariance = np.eye(size)
    return c


def float_image():
    return np.full((360, 480), 128.0)


def negative_length(folder):
    """The nominal H4 with L = -0.29 m, read as `mire fkm --params` reads it."""
    text = open(os.path.join(os.environ["MIRE_SOURCE_DIR"], "datasets/specs/h4_nominal.yaml")).read()
    (folder / "id.yaml").write_text(text.replace("L: 0.30 ", "L: -0.29 "))
    return mech.applyParameterFile(mech.readParameterFile(folder / "id.yaml"),
                                   mech.h4Model12Parameters(mech.H4Nominal()))


def robust_fit_on_joints_of_no_robot():
    """Robust identification on the H4's poses with joints moved by up to ±0.05 rad at random."""
    ids, cTm, joints, covariance = Robot().observe(Robot.protocol(), np.random.default_rng(5))
    joints = joints + np.random.default_rng(7).uniform(-0.05, 0.05, joints.shape)
    poses = mech.observationsFromArrays(ids, cTm, joints, covariance)
    options = mech.IdentificationOptions()
    options.loss = mech.RobustLoss.Huber
    return mech.identify(mech.makeH4VariantModel("D", mech.H4Nominal(), poses), poses, options)


# name -> (call(folder), exception, message fragments). The readers that blocked on a FIFO or
# /dev/zero (class 3 of doc/robustness.md), then the counts, then the calls that returned
# instead of raising (class 6).
READERS = {
    "readPosesCsv": lambda path: mech.readPosesCsv(path),
    "readJointsCsv": lambda path: mech.readJointsCsv(path),
    "readLinesCsv": lambda path: mech.readLinesCsv(path),
    "readObservations": lambda path: mech.readObservations(path, path),
    "readSharedTermCsv": lambda path: mech.readSharedTermCsv(path),
    "readDetectionsFile": lambda path: met.readDetectionsFile(path, small_target()),
}
CASES = {}
for reader, call in READERS.items():
    CASES[f"{reader}Fifo"] = (lambda folder, call=call: call(fifo(folder)), RuntimeError, ["pipe", "FIFO"])
    CASES[f"{reader}DevZero"] = (lambda folder, call=call: call("/dev/zero"), RuntimeError, ["/dev/zero", "device"])
CASES.update({
    "TargetSpecHugeCols": (lambda folder: met.Target(chessboard_spec(10 ** 6, 10 ** 3)), ValueError,
                           ["1000000000 features", "at most 20000"]),
    "TargetSpec400x300": (lambda folder: met.Target(chessboard_spec(400, 300)), ValueError, ["120000 features"]),
    "MonteCarloThreadsMillion": (lambda folder: monte_carlo(10 ** 6), ValueError, ["threads 1000000", "0..256"]),
    "MonteCarloThreadsNegative": (lambda folder: monte_carlo(-1), ValueError, ["threads -1"]),
    "CameraCovarianceWrongSize": (lambda folder: set_camera_covariance(4), ValueError, ["4x4", "9 parameters"]),
    "DetectTargetFloatImage": (lambda folder: met.detectTarget(small_target(), float_image()), ValueError,
                               ["detectTarget", "uint8", "float64"]),
    "DetectAprilTagsFloatImage": (lambda folder: met.detectAprilTags(float_image(), "tag36h11"), ValueError,
                                  ["detectAprilTags", "uint8"]),
    "MeasurePoseNamesMismatch": (lambda folder: met.measurePose(camera(), small_target(),
                                                                 [np.zeros((360, 480), np.uint8)] * 2, ["only_one"]),
                                 ValueError, ["1 names for 2 images"]),
    "MeasurePoseFloatImage": (lambda folder: met.measurePose(camera(), small_target(), [float_image()]), ValueError,
                              ["measurePose: image 0", "uint8"]),
    "SelectModelNoCandidate": (lambda folder: mech.selectModel([], h4_observations(), [], mech.SelectionOptions()),
                               ValueError, ["no candidate model"]),
    "DesignCovarianceEmptyDesign": (lambda folder: mech.designCovariance(design_information(), []), ValueError,
                                    ["design is empty"]),
    "ParameterFileNegativeLength": (negative_length, RuntimeError,
                                    ["id.yaml:5: L = -0.29 m: a length must be positive"]),
    "IdentifyRobustJointsOfNoRobot": (lambda folder: robust_fit_on_joints_of_no_robot(), RuntimeError,
                                      ["the robust fit gave up most poses", "more than half"]),
    "DesignCovarianceIndexOutside": (lambda folder: mech.designCovariance(design_information(), [0, 200]),
                                     ValueError, ["design index 200"]),
})


def snapshot(folder):
    """Every entry under `folder` with its bytes (regular files) or its kind."""
    entries = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = os.path.join(root, name)
            if os.path.isfile(path) and not os.path.islink(path):
                with open(path, "rb") as f:
                    entries[path] = f.read()
            else:
                entries[path] = "<other>"
    return entries


def on_alarm(signum, frame):
    raise TimeoutError(f"no answer within {ALARM_S} s (a hang)")


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_input(name, tmp_path):
    call, exception, fragments = CASES[name]
    before = snapshot(tmp_path)
    previous = signal.signal(signal.SIGALRM, on_alarm)
    signal.alarm(ALARM_S)
    try:
        with pytest.raises(exception) as raised:
            call(tmp_path)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    message = str(raised.value)
    for fragment in fragments:
        assert fragment in message, f"{fragment!r} not in {message!r}"
    after = snapshot(tmp_path)
    # The case's own inputs (a FIFO, a parameter file) are all that is there: nothing was written.
    assert after.keys() == before.keys() | ({str(tmp_path / "pipe"), str(tmp_path / "id.yaml")} & after.keys())
    for path, content in before.items():
        assert after[path] == content, f"modified: {path}"


def test_tag16h5_layout_on_tag36h11_images_measures_nothing(tmp_path):
    """A tag16h5 layout on images of tag36h11 tags: tag16h5 decodes the other family's black squares
    with corrected bits, and one such tag fits its own corners (0.07 px), for a pose 0.24 m and 90°
    off. measurePose must fail naming the likely cause, not return that pose."""
    binary = os.environ.get("MIRE_BINARY")
    if not binary:
        pytest.skip("MIRE_BINARY not set (ctest python_tests sets it): the images are rendered by mire simulate")
    (tmp_path / "camera.yaml").write_text(
        "%YAML:1.0\n---\nimage_width: 480\nimage_height: 360\nmodel: \"opencv\"\n"
        "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
        "   data: [ 420., 0., 239.5, 0., 420., 179.5, 0., 0., 1. ]\n"
        "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
        "   data: [ -0.1, 0.02, 0., 0., 0. ]\n")
    (tmp_path / "target.yaml").write_text("%YAML:1.0\n---\ntype: apriltag\ncols: 3\nrows: 2\nfamily: tag36h11\n"
                                          "tag_size_m: 0.05\ntag_spacing_m: 0.065\nfirst_id: 0\n")
    (tmp_path / "spec.yaml").write_text(
        "%YAML:1.0\n---\ncamera: \"camera.yaml\"\ntarget: \"target.yaml\"\nseed: 4\n"
        "render:\n  supersampling: 2\nnoise:\n  gaussian_sigma: 2.0\n"
        "poses:\n  images_per_pose: 1\n  list:\n"
        "    - { id: \"p1\", t: [ -0.08, -0.05, 0.4 ], r: [ 0.0, 0.0, 0.0 ] }\n"
        "    - { id: \"p2\", t: [ -0.07, -0.04, 0.45 ], r: [ 0.2, 0.1, 0.0 ] }\n")
    subprocess.run([binary, "simulate", "poses", "--spec", str(tmp_path / "spec.yaml"), "-o", str(tmp_path / "sim")],
                   check=True, capture_output=True)
    spec = met.TargetSpec()
    spec.type, spec.cols, spec.rows, spec.family = met.TargetType.AprilTag, 3, 2, "tag16h5"
    spec.tag_size_m, spec.tag_spacing_m, spec.first_id = 0.05, 0.065, 0
    wrong = met.Target(spec)
    spec.family = "tag36h11"
    right = met.Target(spec)
    errors = []
    for pose in ("p1", "p2"):
        folder = tmp_path / "sim" / "poses" / pose
        assert met.measurePoseFromFolder(camera(), right, folder).ok  # the images are fine
        measured = met.measurePoseFromFolder(camera(), wrong, folder)
        assert not measured.ok
        errors.append(measured.error)
    # p1 shows a tag16h5 id of the layout (4), with corrected bits; p2 none at all ("no tag ... found").
    assert any("decoded exactly" in e and "another tag family" in e for e in errors), errors
