"""The bad-input matrix of the Python module (doc/robustness.md), the same shape as the CLI's
(tests/apps/bad_input_cases.cpp): one case per row, each with the exception it must raise, the
fragments its message must hold, and a check that every input file kept its bytes. A reader
that blocked on a FIFO or on /dev/zero would hang: every case runs under a 10 s alarm, so a
regression fails instead of hanging the suite."""
import os
import signal

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
    # The case's own inputs (a FIFO) are all that is there, unchanged: nothing was written.
    assert after.keys() == before.keys() | ({str(tmp_path / "pipe")} & after.keys())
    for path, content in before.items():
        assert after[path] == content, f"modified: {path}"
