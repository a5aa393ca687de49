// The cases of the bad-input matrix (doc/robustness.md), by class: missing and non-regular inputs,
// outputs that would overwrite an input or each other, invalid option values, absurd cameras
// and targets, bad images, bad CSV rows, bad simulation specs, degenerate identifications.
// Exit codes (README): 1 = bad input, 2 = wrong command line.
#include "bad_input_fixture.hpp"

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/registry.hpp"

#include <unistd.h>

#include <cmath>

namespace mire::app::badinput {

std::string posesBlock(const std::string& list);
std::string validPoseList();

namespace {

using Env = const CaseEnv&;

std::string measure(Env e, const std::string& camera, const std::string& target, const std::string& poses,
                    const std::string& extra = "") {
  return "measure --camera " + camera + " --target " + target + " --poses " + poses + " -o " + e.p("out/poses.csv") +
         " " + extra;
}
std::string measureWithCamera(Env e, const std::string& camera) {
  return measure(e, camera, e.target(), e.poses_dir());
}
std::string calibrate(Env e, const std::string& target, const std::string& images, const std::string& extra = "") {
  return "calibrate --target " + target + " --images " + images + " -o " + e.p("out/camera.yaml") + " " + extra;
}
std::string identify(Env e, const std::string& poses, const std::string& joints, const std::string& extra = "") {
  return "identify --poses " + poses + " --joints " + joints + " -o " + e.p("out/params.yaml") + " " + extra;
}
std::string identifyDefault(Env e, const std::string& extra) {
  return identify(e, e.poses_csv(), e.joints_csv(), extra);
}

// camera.yaml of the fixture's camera with some values replaced.
std::string cameraFile(Env e, const std::string& k, const std::string& d, const std::string& extra = "",
                       const std::string& size = "image_width: 480\nimage_height: 360\n") {
  return e.write("camera.yaml",
                 "%YAML:1.0\n---\n" + size + "model: \"opencv\"\n" +
                     "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ " + k +
                     " ]\ndistortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n   data: [ " + d +
                     " ]\n" + extra);
}
const char* kK = "420., 0., 239.5, 0., 420., 179.5, 0., 0., 1.";
const char* kD = "-0.1, 0.02, 0., 0., 0.";

// A 9x9 covariance with `diagonal` on the diagonal and (0,1) = (1,0) = `off`.
std::string covariance(double diagonal, double off, double asymmetric = 0.0) {
  std::string data;
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 9; ++c) {
      double v = r == c ? diagonal : 0.0;
      if ((r == 0 && c == 1) || (r == 1 && c == 0)) v = off;
      if (r == 2 && c == 3) v += asymmetric;
      data += (data.empty() ? "" : ", ") + std::to_string(v);
    }
  return "covariance: !!opencv-matrix\n   rows: 9\n   cols: 9\n   dt: d\n   data: [ " + data + " ]\n";
}

// A copy of a CSV file with one cell (data row `row`, 0-based, column `column`) replaced.
std::string editCsv(Env e, const fs::path& from, const std::string& relative, int row, const std::string& column,
                    const std::string& value) {
  std::stringstream in(slurp(from));
  std::string line, out;
  std::vector<std::string> header;
  int data_row = -1;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out += line + "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream cellstream(line);
    std::string cell;
    while (std::getline(cellstream, cell, ',')) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
    } else if (++data_row == row) {
      for (std::size_t i = 0; i < header.size(); ++i)
        if (header[i] == column && i < cells.size()) cells[i] = value;
    }
    std::string joined;
    for (std::size_t i = 0; i < cells.size(); ++i) joined += (i ? "," : "") + cells[i];
    out += joined + "\n";
  }
  return e.write(relative, out);
}

// Raw bytes of a PNG/JPEG header claiming a size (with the end marker: only the size is wrong).
std::string pngClaiming(std::uint32_t width, std::uint32_t height) {
  std::string png = "\x89PNG\r\n\x1a\n";
  png += std::string("\0\0\0\x0dIHDR", 8);
  for (std::uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) png += static_cast<char>((v >> shift) & 0xFF);
  png += std::string("\x08\x00\x00\x00\x00", 5) + std::string("\0\0\0\0", 4);  // bit depth.., CRC (unchecked here)
  png += std::string("\0\0\0\0IEND\xae\x42\x60\x82", 12);
  return png;
}

std::string truncated(const fs::path& image, double fraction) {
  const std::string bytes = slurp(image);
  return bytes.substr(0, static_cast<std::size_t>(static_cast<double>(bytes.size()) * fraction));
}

// A copy of the calibration images with one image replaced by `bytes` under `name`.
std::string imagesWith(Env e, const std::string& name, const std::string& bytes) {
  e.copy(e.f.cal / "images", "images");
  e.write("images/" + name, bytes);
  return e.p("images");
}
// A pose folder holding only pose p1, with one file added or replaced (its only pose fails:
// nothing is written, exit 1).
std::string posesWith(Env e, const std::string& name, const std::string& bytes) {
  e.copy(e.f.sim / "poses/p1", "poses/p1");
  e.write("poses/p1/" + name, bytes);
  return e.p("poses");
}
std::string firstPoseImage(Env e) { return (e.f.sim / "poses/p1/img_00.png").string(); }

std::string specWith(Env e, const std::string& list, const std::string& camera_text = "") {
  e.copy(e.f.root / "specs/target.yaml", "target.yaml");
  if (camera_text.empty())
    e.copy(e.f.root / "specs/camera.yaml", "camera.yaml");
  else
    e.write("camera.yaml", camera_text);
  const std::string spec = slurp(e.f.spec);
  const auto at = spec.find("poses:");
  return e.write("spec.yaml", spec.substr(0, at) + posesBlock(list));
}

void add(std::vector<Case>& cases, std::string name, std::function<std::string(Env)> arguments, int code,
         std::vector<std::string> message) {
  cases.push_back({std::move(name), std::move(arguments), code, std::move(message)});
}

// ---- missing, non-regular inputs: exit 1, the option and the path named, never a hang ----
void inputCases(std::vector<Case>& c) {
  struct Input {
    std::string name, option;
    std::function<std::string(Env, const std::string&)> command;
  };
  const std::vector<Input> inputs = {
      {"CalibrateTarget", "--target", [](Env e, const std::string& x) { return calibrate(e, x, e.images()); }},
      {"MeasureCamera", "--camera", [](Env e, const std::string& x) { return measure(e, x, e.target(), e.poses_dir()); }},
      {"MeasureTarget", "--target", [](Env e, const std::string& x) { return measure(e, e.camera(), x, e.poses_dir()); }},
      {"IdentifyPoses", "--poses", [](Env e, const std::string& x) { return identify(e, x, e.joints_csv()); }},
      {"IdentifyJoints", "--joints", [](Env e, const std::string& x) { return identify(e, e.poses_csv(), x); }},
      {"IdentifyCovariances", "--pose-covariances",
       [](Env e, const std::string& x) { return identifyDefault(e, "--pose-covariances " + x); }},
      {"IdentifyNominal", "--nominal", [](Env e, const std::string& x) { return identifyDefault(e, "--nominal " + x); }},
      {"IdentifyLines", "--lines", [](Env e, const std::string& x) { return identifyDefault(e, "--lines " + x); }},
      {"SimulatePosesSpec", "--spec",
       [](Env e, const std::string& x) { return "simulate poses --spec " + x + " -o " + e.p("out"); }},
      {"SimulateCalibrationSpec", "--spec",
       [](Env e, const std::string& x) { return "simulate calibration --spec " + x + " -o " + e.p("out"); }},
  };
  for (const Input& input : inputs) {
    const auto command = input.command;
    add(c, input.name + "Missing", [command](Env e) { return command(e, e.p("absent.file")); }, 1,
        {input.option, "absent.file", "no such file"});
    add(c, input.name + "Fifo", [command](Env e) { return command(e, e.fifo("pipe")); }, 1,
        {input.option, "pipe", "FIFO"});
    add(c, input.name + "Folder", [command](Env e) { return command(e, e.folder("afolder")); }, 1,
        {input.option, "afolder", "is a folder"});
    add(c, input.name + "Device", [command](Env e) { return command(e, "/dev/zero"); }, 1,
        {input.option, "/dev/zero", "device"});
  }
  add(c, "CalibrateImagesMissing", [](Env e) { return calibrate(e, e.cal_target(), e.p("nofolder")); }, 1,
      {"--images", "nofolder", "no such folder"});
  add(c, "CalibrateImagesIsFile", [](Env e) { return calibrate(e, e.cal_target(), e.cal_target()); }, 1,
      {"--images", "is a file"});
  add(c, "MeasurePosesMissing", [](Env e) { return measure(e, e.camera(), e.target(), e.p("nofolder")); }, 1,
      {"--poses", "nofolder", "no such folder"});
  add(c, "MeasurePosesIsFile", [](Env e) { return measure(e, e.camera(), e.target(), e.camera()); }, 1,
      {"--poses", "is a file"});
  add(c, "CalibrateImagesEmpty", [](Env e) { return calibrate(e, e.cal_target(), e.folder("empty")); }, 1,
      {"empty", "holds no image"});
  add(c, "MeasurePosesEmpty", [](Env e) { return measure(e, e.camera(), e.target(), e.folder("empty")); }, 1,
      {"empty", "no pose subfolders"});
}

// ---- outputs: never an input, never another output (also via links and '..') ----
void outputCases(std::vector<Case>& c) {
  add(c, "CalibrateOutputIsTarget",
      [](Env e) {
        const std::string target = e.copy(e.f.cal / "target.yaml", "target.yaml");
        return "calibrate --target " + target + " --images " + e.images() + " -o " + target;
      },
      2, {"-o", "is the input --target", "overwritten"});
  add(c, "CalibrateOutputIsImage",
      [](Env e) {
        return "calibrate --target " + e.cal_target() + " --images " + e.images() + " -o " + e.images() +
               "/view_000.png";
      },
      2, {"inside the input folder --images"});
  add(c, "CalibrateOutputInsideImages",
      [](Env e) {
        return "calibrate --target " + e.cal_target() + " --images " + e.images() + " -o " + e.images() + "/camera.yaml";
      },
      2, {"inside the input folder"});
  add(c, "CalibrateOutputViaDotDot",
      [](Env e) {
        const std::string target = e.copy(e.f.cal / "target.yaml", "target.yaml");
        e.folder("sub");
        return "calibrate --target " + target + " --images " + e.images() + " -o " + e.p("sub/../target.yaml");
      },
      2, {"is the input --target"});
  add(c, "CalibrateOutputViaSymlink",
      [](Env e) {
        const std::string target = e.copy(e.f.cal / "target.yaml", "target.yaml");
        fs::create_symlink(target, e.dir / "link.yaml");
        return "calibrate --target " + target + " --images " + e.images() + " -o " + e.p("link.yaml");
      },
      2, {"is the input --target"});
  add(c, "CalibrateOutputViaHardLink",
      [](Env e) {
        const std::string target = e.copy(e.f.cal / "target.yaml", "target.yaml");
        fs::create_hard_link(target, e.dir / "hard.yaml");
        return "calibrate --target " + target + " --images " + e.images() + " -o " + e.p("hard.yaml");
      },
      2, {"is the input --target"});
  add(c, "CalibrateOutputInReport",
      [](Env e) { return calibrate(e, e.cal_target(), e.images(), "--report " + e.p("out")); }, 2,
      {"would overwrite each other"});
  add(c, "CalibrateReportHoldsTarget",
      [](Env e) {
        const std::string target = e.copy(e.f.cal / "target.yaml", "rep/target.yaml");
        return calibrate(e, target, e.images(), "--report " + e.p("rep"));
      },
      2, {"holds the input --target"});
  add(c, "CalibrateOutputEmpty",
      [](Env e) { return "calibrate --target " + e.cal_target() + " --images " + e.images() + " -o ''"; }, 2,
      {"-o: empty path"});
  add(c, "CalibrateOutputParentIsFile",
      [](Env e) {
        e.write("plain", "x");
        return "calibrate --target " + e.cal_target() + " --images " + e.images() + " -o " + e.p("plain/camera.yaml");
      },
      1, {"plain", "is not a folder"});
  add(c, "CalibrateOutputIsFolder",
      [](Env e) {
        return "calibrate --target " + e.cal_target() + " --images " + e.images() + " -o " + e.folder("adir");
      },
      1, {"adir", "not a regular file"});
  add(c, "MeasureOutputIsCamera",
      [](Env e) {
        const std::string camera = e.copy(e.f.sim / "camera.yaml", "camera.yaml");
        return "measure --camera " + camera + " --target " + e.target() + " --poses " + e.poses_dir() + " -o " + camera;
      },
      2, {"is the input --camera"});
  add(c, "MeasureOutputIsTarget",
      [](Env e) {
        const std::string target = e.copy(e.f.sim / "target.yaml", "target.yaml");
        return "measure --camera " + e.camera() + " --target " + target + " --poses " + e.poses_dir() + " -o " + target;
      },
      2, {"is the input --target"});
  add(c, "MeasureCovarianceIsCamera",
      [](Env e) {
        const std::string camera = e.copy(e.f.sim / "camera.yaml", "camera.yaml");
        return measure(e, camera, e.target(), e.poses_dir(), "--covariance " + camera);
      },
      2, {"--covariance", "is the input --camera"});
  add(c, "MeasureOutputIsCovariance",
      [](Env e) { return measure(e, e.camera(), e.target(), e.poses_dir(), "--covariance " + e.p("out/poses.csv")); },
      2, {"would overwrite each other"});
  add(c, "MeasureDefaultCovarianceIsCamera",
      [](Env e) {
        const std::string camera = e.copy(e.f.sim / "camera.yaml", "p_covariance.csv");
        return "measure --camera " + camera + " --target " + e.target() + " --poses " + e.poses_dir() + " -o " +
               e.p("p.csv");
      },
      2, {"covariance side file", "is the input --camera"});
  add(c, "MeasureOutputIsPoseImage",
      [](Env e) {
        return "measure --camera " + e.camera() + " --target " + e.target() + " --poses " + e.poses_dir() + " -o " +
               firstPoseImage(e);
      },
      2, {"inside the input folder --poses"});
  add(c, "MeasureOutputEmpty",
      [](Env e) {
        return "measure --camera " + e.camera() + " --target " + e.target() + " --poses " + e.poses_dir() + " -o ''";
      },
      2, {"-o: empty path"});
  add(c, "MeasureCovarianceParentIsFile",
      [](Env e) {
        e.write("plain", "x");
        return measure(e, e.camera(), e.target(), e.poses_dir(), "--covariance " + e.p("plain/cov.csv"));
      },
      1, {"plain", "is not a folder"});
  const std::vector<std::pair<std::string, std::string>> identify_inputs = {
      {"Poses", "poses.csv"}, {"Joints", "joints.csv"}, {"Lines", "lines.csv"}};
  for (const auto& [name, file] : identify_inputs) {
    const std::string f = file;
    add(c, "IdentifyOutputIs" + name,
        [f](Env e) {
          e.copy(e.f.campaign / "poses.csv", "poses.csv");
          e.copy(e.f.campaign / "joints.csv", "joints.csv");
          e.copy(e.f.campaign / "lines.csv", "lines.csv");
          return "identify --poses " + e.p("poses.csv") + " --joints " + e.p("joints.csv") + " --lines " +
                 e.p("lines.csv") + " -o " + e.p(f);
        },
        2, {"-o", "is the input", "overwritten"});
  }
  add(c, "IdentifyOutputIsCovariances",
      [](Env e) {
        const std::string cov = e.write("cov.csv", "pose_id,part,row,tx,ty,tz,rx,ry,rz\n");
        return "identify --poses " + e.poses_csv() + " --joints " + e.joints_csv() + " --pose-covariances " + cov +
               " -o " + cov;
      },
      2, {"is the input --pose-covariances"});
  add(c, "IdentifyOutputIsNominal",
      [](Env e) {
        const std::string nominal = e.copy(test::sourceDir() / "datasets/specs/h4_nominal.yaml", "nominal.yaml");
        return "identify --poses " + e.poses_csv() + " --joints " + e.joints_csv() + " --nominal " + nominal + " -o " +
               nominal;
      },
      2, {"is the input --nominal"});
  add(c, "IdentifyOutputInReport", [](Env e) { return identifyDefault(e, "--report " + e.p("out")); }, 2,
      {"would overwrite each other"});
  add(c, "IdentifyReportIsOutput", [](Env e) { return identifyDefault(e, "--report " + e.p("out/params.yaml")); }, 2,
      {"would overwrite each other"});
  add(c, "IdentifyReportHoldsPoses",
      [](Env e) {
        e.copy(e.f.campaign / "poses.csv", "rep/poses.csv");
        return identify(e, e.p("rep/poses.csv"), e.joints_csv(), "--report " + e.p("rep"));
      },
      2, {"holds the input --poses"});
  add(c, "IdentifyOutputEmpty",
      [](Env e) { return "identify --poses " + e.poses_csv() + " --joints " + e.joints_csv() + " -o ''"; }, 2,
      {"-o: empty path"});
  add(c, "IdentifyOutputParentIsFile",
      [](Env e) {
        e.write("plain", "x");
        return "identify --poses " + e.poses_csv() + " --joints " + e.joints_csv() + " -o " + e.p("plain/x.yaml");
      },
      1, {"plain", "is not a folder"});
  add(c, "SimulateOutputIsSpecFile",
      [](Env e) {
        const std::string spec = specWith(e, validPoseList());
        return "simulate poses --spec " + spec + " -o " + spec;
      },
      2, {"is the input --spec"});
  add(c, "SimulateOutputHoldsSpec",
      [](Env e) {
        const std::string spec = specWith(e, validPoseList());
        return "simulate poses --spec " + spec + " -o " + e.dir.string();
      },
      2, {"holds the input --spec"});
  add(c, "SimulateOutputNotASimulation",
      [](Env e) {
        e.write("mine/notes.txt", "my notes");
        return "simulate poses --spec " + e.f.spec.string() + " -o " + e.p("mine");
      },
      2, {"mine", "not a previous simulation"});
  add(c, "SimulateOutputEmpty", [](Env e) { return "simulate poses --spec " + e.f.spec.string() + " -o ''"; }, 2,
      {"-o: empty path"});
  add(c, "SimulateOutputIsFile",
      [](Env e) { return "simulate calibration --spec " + e.f.cal_spec.string() + " -o " + e.write("plain", "x"); }, 1,
      {"plain", "not a folder"});
}

// ---- option values: exit 2, the option named ----
void optionCases(std::vector<Case>& c) {
  const std::vector<std::pair<std::string, std::string>> threads = {
      {"Negative", "-1"}, {"Huge", "100000"}, {"Text", "many"}};
  for (const auto& [name, value] : threads) {
    const std::string v = value;
    add(c, "CalibrateThreads" + name, [v](Env e) { return calibrate(e, e.cal_target(), e.images(), "--threads " + v); },
        2, {"--threads"});
    add(c, "MeasureThreads" + name,
        [v](Env e) { return measure(e, e.camera(), e.target(), e.poses_dir(), "--threads " + v); }, 2, {"--threads"});
    add(c, "IdentifyThreads" + name, [v](Env e) { return identifyDefault(e, "--mc 15 --threads " + v); }, 2,
        {"--threads"});
  }
  add(c, "IdentifyThreadsZero", [](Env e) { return identifyDefault(e, "--threads 0"); }, 2, {"--threads"});
  for (const std::string value : {"nan", "-1", "inf", "0", "abc"}) {
    add(c, "MeasureAmbiguityRatio_" + std::string(value == "-1" ? "minus1" : value),
        [value](Env e) { return measure(e, e.camera(), e.target(), e.poses_dir(), "--ambiguity-ratio " + value); }, 2,
        {"--ambiguity-ratio"});
  }
  for (const std::string value : {"nan", "2", "0.1"}) {
    add(c,
        "MeasureRejectionConfidence_" + std::string(value == "0.1" ? "low"
                                                    : value == "2" ? "high"
                                                                   : value),
        [value](Env e) { return measure(e, e.camera(), e.target(), e.poses_dir(), "--rejection-confidence " + value); },
        2, {"--rejection-confidence"});
  }
  add(c, "CalibrateModelUnknown", [](Env e) { return calibrate(e, e.cal_target(), e.images(), "--model opencv7"); }, 2,
      {"--model"});
  const std::vector<std::tuple<std::string, std::string, std::string>> identify = {
      {"McEmptyEntry", "--mc 6,,15", "--mc"},
      {"McOne", "--mc 1", "--mc 1"},
      {"McZero", "--mc 0", "--mc"},
      {"McText", "--mc six", "--mc"},
      {"McNegative", "--mc -5", "--mc"},
      {"McAllPoses", "--mc 100000", "--mc 100000"},
      {"McRepeatsWithoutMc", "--mc-repeats 20", "--mc-repeats"},
      {"McSeedWithoutMc", "--mc-seed 5", "--mc-seed"},
      {"McSeedNegative", "--mc 15 --mc-seed -1", "--mc-seed"},
      {"McRepeatsZero", "--mc 15 --mc-repeats 0", "--mc-repeats"},
      {"PriorTinySigma", "--prior R=0.2:1e-300", "--prior 'R=0.2:1e-300'"},
      {"PriorZeroSigma", "--prior R=0.2:0", "--prior"},
      {"PriorNegativeSigma", "--prior R=0.2:-1", "--prior"},
      {"PriorNanValue", "--prior R=nan:0.001", "--prior"},
      {"PriorText", "--prior R=abc:0.001", "--prior"},
      {"PriorNoEquals", "--prior R0.2", "--prior"},
      {"VariantUnknown", "--variant Z", "--variant 'Z'"},
      {"VariantTwoLetters", "--variant AB", "--variant 'AB'"},
      {"VariantWrongModel", "--model h4-31c --variant A", "--variant A"},
      {"ModelUnknown", "--model h5", "--model 'h5'"},
      {"UnweightedWithCovariances", "--unweighted --pose-covariances " + std::string("/dev/null"), "--unweighted"},
      {"ObservationsUnknown", "--observations feet --legs /dev/null", "--observations"},
      {"LegsWithoutObservations", "--legs /dev/null", "--legs needs --observations"},
      {"ObservationsLegsWithoutLegs", "--observations legs", "needs --legs"},
      {"ObservationsBothWithReport", "--observations both --legs /dev/null --report /tmp/x", "--report does not apply"},
  };
  for (const auto& [name, extra, message] : identify) {
    const std::string x = extra;
    add(c, "Identify" + name, [x](Env e) { return identifyDefault(e, x); }, 2, {message});
  }
  add(c, "UnknownSubcommand", [](Env) { return std::string("calibrat --target x"); }, 2,
      {"unknown subcommand 'calibrat'"});
  add(c, "CalibrateMissingRequired",
      [](Env e) { return "calibrate --target " + e.cal_target() + " -o " + e.p("out/camera.yaml"); }, 2, {"--images"});
  add(c, "MeasureUnknownOption", [](Env e) { return measure(e, e.camera(), e.target(), e.poses_dir(), "--fast"); }, 2,
      {"--fast"});
  add(c, "SimulateNoKind", [](Env e) { return "simulate --spec " + e.f.spec.string(); }, 2, {"subcommand"});
}

// ---- cameras and targets that would give absurd answers: exit 1, the file named ----
void cameraTargetCases(std::vector<Case>& c) {
  add(c, "CameraPrincipalPointOutside",
      [](Env e) { return measureWithCamera(e, cameraFile(e, "420., 0., -5000., 0., 420., 179.5, 0., 0., 1.", kD)); }, 1,
      {"camera.yaml", "principal point"});
  add(c, "CameraPrincipalPointBelow",
      [](Env e) { return measureWithCamera(e, cameraFile(e, "420., 0., 239.5, 0., 420., 9000., 0., 0., 1.", kD)); }, 1,
      {"camera.yaml", "principal point"});
  add(c, "CameraHugeK1", [](Env e) { return measureWithCamera(e, cameraFile(e, kK, "1.0e6, 0.02, 0., 0., 0.")); }, 1,
      {"camera.yaml", "distortion_coefficients"});
  add(c, "CameraHugeK3", [](Env e) { return measureWithCamera(e, cameraFile(e, kK, "-0.1, 0.02, 0., 0., -5.0e4")); }, 1,
      {"camera.yaml", "distortion_coefficients"});
  add(c, "CameraK1Hundred", [](Env e) { return measureWithCamera(e, cameraFile(e, kK, "100., 0.02, 0., 0., 0.")); }, 1,
      {"camera.yaml", "stretches the image corner", "k1 = 100"});
  add(c, "ConvertCameraK1Hundred",
      [](Env e) {
        return "convert --camera " + cameraFile(e, kK, "100., 0.02, 0., 0., 0.") + " --to ros -o " + e.p("out/cam.yaml");
      },
      1, {"camera.yaml", "stretches the image corner"});
  add(c, "CameraZeroFx",
      [](Env e) { return measureWithCamera(e, cameraFile(e, "0., 0., 239.5, 0., 420., 179.5, 0., 0., 1.", kD)); }, 1,
      {"camera.yaml"});
  add(c, "CameraNegativeFy",
      [](Env e) { return measureWithCamera(e, cameraFile(e, "420., 0., 239.5, 0., -420., 179.5, 0., 0., 1.", kD)); }, 1,
      {"camera.yaml"});
  add(c, "CameraFxFarFromFy",
      [](Env e) { return measureWithCamera(e, cameraFile(e, "42000., 0., 239.5, 0., 420., 179.5, 0., 0., 1.", kD)); },
      1, {"camera.yaml", "fx"});
  add(c, "CameraCovarianceNotPositive",
      [](Env e) { return measureWithCamera(e, cameraFile(e, kK, kD, covariance(1e-2, 2e-2))); }, 1,
      {"camera.yaml", "covariance", "positive semi-definite"});
  add(c, "CameraCovarianceNegativeVariance",
      [](Env e) { return measureWithCamera(e, cameraFile(e, kK, kD, covariance(-1e-2, 0.0))); }, 1,
      {"camera.yaml", "covariance"});
  add(c, "CameraCovarianceAsymmetric",
      [](Env e) { return measureWithCamera(e, cameraFile(e, kK, kD, covariance(1e-2, 0.0, 5e-3))); }, 1,
      {"camera.yaml", "covariance"});
  add(c, "CameraHugeImage",
      [](Env e) { return measureWithCamera(e, cameraFile(e, kK, kD, "", "image_width: 65536\nimage_height: 65536\n")); },
      1, {"camera.yaml", "65536"});
  add(c, "TargetMillimetresMeasure",
      [](Env e) {
        return measure(e, e.camera(), e.edit(e.f.sim / "target.yaml", "target.yaml", "0.02", "20"), e.poses_dir());
      },
      1, {"target.yaml", "millimetres", "square_size_m: 0.025"});
  add(c, "TargetMillimetresCalibrate",
      [](Env e) { return calibrate(e, e.edit(e.f.cal / "target.yaml", "target.yaml", "0.02", "20"), e.images()); }, 1,
      {"target.yaml", "millimetres"});
  add(c, "TargetMicrometresMeasure",
      [](Env e) {
        return measure(e, e.camera(), e.edit(e.f.sim / "target.yaml", "target.yaml", "0.02", "2e-7"), e.poses_dir());
      },
      1, {"target.yaml", "wrong unit"});
  add(c, "TargetSquare1e50Measure",
      [](Env e) {
        return measure(e, e.camera(), e.edit(e.f.sim / "target.yaml", "target.yaml", "0.02", "1e50"), e.poses_dir());
      },
      1, {"target.yaml"});
  add(c, "TargetSquare1e50Calibrate",
      [](Env e) { return calibrate(e, e.edit(e.f.cal / "target.yaml", "target.yaml", "0.02", "1e50"), e.images()); }, 1,
      {"target.yaml"});
  add(c, "TargetTooManyFeatures",
      [](Env e) {
        const std::string target =
            e.write("target.yaml", "%YAML:1.0\n---\ntype: chessboard\ncols: 201\nrows: 200\nsquare_size_m: 0.001\n");
        return measure(e, e.camera(), target, e.poses_dir());
      },
      1, {"target.yaml", "40200 features"});
  add(c, "TargetTooManyFeaturesCalibrate",
      [](Env e) {
        const std::string target =
            e.write("target.yaml", "%YAML:1.0\n---\ntype: chessboard\ncols: 201\nrows: 200\nsquare_size_m: 0.001\n");
        return calibrate(e, target, e.images());
      },
      1, {"target.yaml", "40200 features"});
}

// ---- images: too large, truncated, blank, tiny; exit 1 naming the image ----
void imageCases(std::vector<Case>& c) {
  add(c, "CalibratePngClaims20000",
      [](Env e) { return calibrate(e, e.cal_target(), imagesWith(e, "huge.png", pngClaiming(20000, 20000))); }, 1,
      {"huge.png", "20000x20000", "megapixels"});
  add(c, "CalibratePngClaimsWide",
      [](Env e) { return calibrate(e, e.cal_target(), imagesWith(e, "wide.png", pngClaiming(70000, 10))); }, 1,
      {"wide.png", "70000x10"});
  add(c, "CalibrateBmpClaimsHuge",
      [](Env e) {
        std::string bmp = "BM" + std::string(24, '\0');
        const std::uint32_t side = 30000;
        for (int at : {18, 22})
          for (int i = 0; i < 4; ++i)
            bmp[static_cast<std::size_t>(at + i)] = static_cast<char>((side >> (8 * i)) & 0xFF);
        return calibrate(e, e.cal_target(), imagesWith(e, "huge.bmp", bmp));
      },
      1, {"huge.bmp", "30000x30000"});
  add(c, "CalibratePgmClaimsHuge",
      [](Env e) { return calibrate(e, e.cal_target(), imagesWith(e, "huge.pgm", "P5\n# big\n40000 40000\n255\n")); }, 1,
      {"huge.pgm", "40000x40000"});
  add(c, "CalibrateJpegClaimsHuge",
      [](Env e) {
        // SOI, SOF0 (length 11, 8 bit, height 30000, width 30000, 1 component), EOI.
        const std::string jpeg = std::string("\xFF\xD8\xFF\xC0\x00\x0B\x08\x75\x30\x75\x30\x01\x01\x11\x00\xFF\xD9", 17);
        return calibrate(e, e.cal_target(), imagesWith(e, "huge.jpg", jpeg));
      },
      1, {"huge.jpg", "30000x30000"});
  add(c, "CalibrateTruncatedPng",
      [](Env e) {
        return calibrate(e, e.cal_target(),
                         imagesWith(e, "view_000.png", truncated(e.f.cal / "images/view_000.png", 0.6)));
      },
      1, {"view_000.png", "truncated"});
  add(c, "CalibrateTruncatedJpeg",
      [](Env e) {
        const std::string jpeg = std::string("\xFF\xD8\xFF\xE0\x00\x10JFIF\x00\x01\x01\x00\x00\x01\x00\x01\x00\x00", 20);
        return calibrate(e, e.cal_target(), imagesWith(e, "cut.jpg", jpeg));
      },
      1, {"cut.jpg", "truncated"});
  add(c, "CalibrateGarbageImage",
      [](Env e) { return calibrate(e, e.cal_target(), imagesWith(e, "garbage.png", "not an image")); }, 1,
      {"garbage.png"});
  add(c, "CalibrateEmptyImageFile", [](Env e) { return calibrate(e, e.cal_target(), imagesWith(e, "empty.png", "")); },
      1, {"empty.png"});
  for (int side : {1, 2, 8}) {
    add(c, "CalibrateTinyImage" + std::to_string(side),
        [side](Env e) {
          // A valid PGM of side x side: read, the size differs from the others.
          std::string pgm = "P5\n" + std::to_string(side) + " " + std::to_string(side) + "\n255\n" +
                            std::string(static_cast<std::size_t>(side * side), '\x80');
          return calibrate(e, e.cal_target(), imagesWith(e, "zz_tiny.pgm", pgm));
        },
        1, {"zz_tiny.pgm", std::to_string(side) + "x" + std::to_string(side)});
  }
  add(c, "CalibrateOnlyTinyImages",
      [](Env e) {
        for (int i = 0; i < 3; ++i)
          e.write("tiny/t" + std::to_string(i) + ".pgm", "P5\n2 2\n255\n" + std::string(4, '\x80'));
        return calibrate(e, e.cal_target(), e.p("tiny"));
      },
      1, {"tiny"});
  add(c, "MeasureTruncatedPoseImage",
      [](Env e) {
        return measure(e, e.camera(), e.target(), posesWith(e, "img_00.png", truncated(firstPoseImage(e), 0.5)));
      },
      1, {"pose p1", "img_00.png", "truncated"});
  add(c, "MeasureBlankPoseImage",
      [](Env e) {
        return measure(e, e.camera(), e.target(),
                       posesWith(e, "img_09.pgm", "P5\n480 360\n255\n" + std::string(480 * 360, '\x80')));
      },
      1, {"pose p1", "img_09.pgm", "blank"});
  add(c, "MeasureHugePoseImage",
      [](Env e) { return measure(e, e.camera(), e.target(), posesWith(e, "img_09.png", pngClaiming(20000, 20000))); },
      1, {"pose p1", "img_09.png", "20000x20000"});
  add(c, "MeasureGarbagePoseImage",
      [](Env e) { return measure(e, e.camera(), e.target(), posesWith(e, "img_09.png", "garbage")); }, 1,
      {"pose p1", "img_09.png"});
  add(c, "MeasureEveryPoseBlank",
      [](Env e) {
        const std::string blank = "P5\n480 360\n255\n" + std::string(480 * 360, '\x10');
        e.write("poses/a/img.pgm", blank);
        e.write("poses/b/img.pgm", blank);
        return measure(e, e.camera(), e.target(), e.p("poses"));
      },
      1, {"no pose could be measured", "blank"});
  add(c, "MeasurePoseIdWithComma",
      [](Env e) {
        e.copy(e.f.sim / "poses/p1", "poses/a,b");
        return measure(e, e.camera(), e.target(), e.p("poses"));
      },
      1, {"a,b", "must not contain"});
}

// ---- identify's CSV inputs: exit 1 naming file and line/pose ----
void csvCases(std::vector<Case>& c) {
  const auto posesEdit = [](int row, std::string column, std::string value) {
    return [row, column, value](Env e) {
      return identify(e, editCsv(e, e.f.campaign / "poses.csv", "poses.csv", row, column, value), e.joints_csv());
    };
  };
  add(c, "PosesRotationBeyondTwoPi", posesEdit(3, "rx_rad", "100"), 1, {"poses.csv", "rotation vector", "2π"});
  add(c, "PosesRotationNegativeBeyondTwoPi", posesEdit(0, "rz_rad", "-7"), 1, {"poses.csv", "rotation vector"});
  add(c, "PosesNanTranslation", posesEdit(2, "tx_m", "nan"), 1, {"poses.csv", "tx_m"});
  add(c, "PosesTextTranslation", posesEdit(2, "ty_m", "abc"), 1, {"poses.csv", "ty_m"});
  add(c, "PosesRangeError", posesEdit(2, "tz_m", "1e400"), 1, {"poses.csv", "tz_m"});
  add(c, "PosesEmptyCell", posesEdit(1, "rx_rad", ""), 1, {"poses.csv", "rx_rad"});
  add(c, "PosesDuplicateId", posesEdit(1, "pose_id", "1"), 1, {"poses.csv"});
  add(c, "PosesOneSigmaZero", posesEdit(4, "sigma_tx_mm", "0"), 1,
      {"poses.csv", "no usable covariance", "--unweighted"});
  add(c, "PosesNegativeSigma", posesEdit(4, "sigma_rx_deg", "-0.03"), 1, {"poses.csv"});
  add(c, "PosesMissingColumn",
      [](Env e) { return identify(e, e.edit(e.f.campaign / "poses.csv", "poses.csv", "tz_m", "tzz_m"), e.joints_csv()); },
      1, {"poses.csv", "tz_m"});
  add(c, "LegsCsvLegOutOfRange",
      [](Env e) {
        return identifyDefault(e, "--observations legs --model gough-stewart --legs " +
                                      e.write("legs.csv",
                                              "pose_id,leg,dx,dy,dz,mx_m,my_m,mz_m,c11,c12,c13,c14,c22,c23,c24,c33,c34,"
                                              "c44\n1,9,0,0,1,0.1,0.2,0,1e-6,0,0,0,1e-6,0,0,1e-6,0,1e-6\n"));
      },
      1, {"legs.csv:2", "leg 9"});
  add(c, "PosesEmptyFile", [](Env e) { return identify(e, e.write("poses.csv", ""), e.joints_csv()); }, 1, {"poses.csv"});
  add(c, "PosesHeaderOnly",
      [](Env e) {
        const std::string text = slurp(e.f.campaign / "poses.csv");
        return identify(e, e.write("poses.csv", text.substr(0, text.find('\n') + 1)), e.joints_csv());
      },
      1, {"poses.csv"});
  add(c, "PosesShortRow",
      [](Env e) {
        return identify(e, e.write("poses.csv", slurp(e.f.campaign / "poses.csv") + "99,1,2\n"), e.joints_csv());
      },
      1, {"poses.csv", "columns"});
  add(c, "PosesBinaryGarbage",
      [](Env e) { return identify(e, e.write("poses.csv", std::string("\x00\x01\xff\xfe", 4)), e.joints_csv()); }, 1,
      {"poses.csv"});
  add(c, "JointsNan",
      [](Env e) {
        return identify(e, e.poses_csv(), editCsv(e, e.f.campaign / "joints.csv", "joints.csv", 2, "q2_rad", "nan"));
      },
      1, {"joints.csv", "q2_rad"});
  add(c, "JointsMissingPose",
      [](Env e) {
        std::string text = slurp(e.f.campaign / "joints.csv");
        const auto second = text.find('\n', text.find('\n') + 1);
        return identify(e, e.poses_csv(),
                        e.write("joints.csv", text.substr(0, text.find('\n') + 1) + text.substr(second + 1)));
      },
      1, {"poses.csv"});
  add(c, "JointsMissingColumn",
      [](Env e) {
        return identify(e, e.poses_csv(), e.edit(e.f.campaign / "joints.csv", "joints.csv", "q4_rad", "q5_rad"));
      },
      1, {"joints.csv", "q4_rad"});
  add(c, "LinesNan",
      [](Env e) {
        return identifyDefault(e, "--lines " + editCsv(e, e.f.campaign / "lines.csv", "lines.csv", 1, "q1_rad", "inf"));
      },
      1, {"lines.csv", "q1_rad"});
  add(c, "CovarianceSideNotPositive",
      [](Env e) {
        std::string text = "pose_id,part,row,tx,ty,tz,rx,ry,rz\n";
        std::stringstream poses(slurp(e.f.campaign / "poses.csv"));
        std::string line;
        std::getline(poses, line);
        while (std::getline(poses, line)) {
          if (line.empty() || line[0] == '#') continue;
          const std::string id = line.substr(0, line.find(','));
          for (int r = 0; r < 6; ++r) {
            text += id + ",total," + std::to_string(r);
            for (int col = 0; col < 6; ++col) text += r == col ? ",-1e-8" : ",0";
            text += "\n";
          }
        }
        return identifyDefault(e, "--pose-covariances " + e.write("cov.csv", text));
      },
      1, {"cov.csv"});
  add(c, "CovarianceSideMissingPose",
      [](Env e) {
        return identifyDefault(e, "--pose-covariances " + e.write("cov.csv", "pose_id,part,row,tx,ty,tz,rx,ry,rz\n"));
      },
      1, {"cov.csv"});
  add(c, "NominalUnknownKey",
      [](Env e) { return identifyDefault(e, "--nominal " + e.write("nominal.yaml", "R: 0.2\nRR: 0.3\n")); }, 1,
      {"nominal.yaml", "RR"});
  add(c, "NominalNotANumber",
      [](Env e) { return identifyDefault(e, "--nominal " + e.write("nominal.yaml", "R: abc\n")); }, 1,
      {"nominal.yaml", "R"});
  add(c, "IdentifyFixEverything",
      [](Env e) {
        return identifyDefault(
            e,
            "--fix R,L,l,h,d,alpha1,alpha2,alpha3,alpha4,q01,q02,q03,q04,x_BC,y_BC,z_BC,psi_BC,x_ME,y_ME,z_ME,psi_ME");
      },
      1, {"free parameter"});
  add(c, "IdentifyFixUnknown", [](Env e) { return identifyDefault(e, "--fix Rr"); }, 1, {"Rr"});
  add(c, "IdentifyPriorUnknown", [](Env e) { return identifyDefault(e, "--prior Q=1:0.1"); }, 1, {"Q"});
}

// ---- simulation specs: exit 1 naming the spec and the pose ----
void specCases(std::vector<Case>& c) {
  const std::vector<std::tuple<std::string, std::string, std::vector<std::string>>> lists = {
      {"DuplicateId",
       "    - { id: \"p1\", t: [ 0.0, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n"
       "    - { id: \"p1\", t: [ 0.01, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n",
       {"spec.yaml", "'p1' is given twice"}},
      {"DotDotId", "    - { id: \"..\", t: [ 0.0, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n", {"spec.yaml", "'..'"}},
      {"DotId", "    - { id: \".\", t: [ 0.0, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n", {"spec.yaml"}},
      {"HiddenId", "    - { id: \".hidden\", t: [ 0.0, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n", {"spec.yaml", ".hidden"}},
      {"CommaId", "    - { id: \"a,b\", t: [ 0.0, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n", {"spec.yaml", "a,b"}},
      {"SlashId", "    - { id: \"a/b\", t: [ 0.0, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n", {"spec.yaml"}},
      {"NanTranslation", "    - { id: \"p1\", t: [ .nan, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n", {"spec.yaml"}},
      {"BehindCamera",
       "    - { id: \"p1\", t: [ 0.0, 0.0, -0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n",
       {"spec.yaml", "behind the camera"}},
      {"InCameraPlane",
       "    - { id: \"p1\", t: [ 0.0, 0.0, 0.0 ], r: [ 0.0, 0.0, 0.0 ] }\n",
       {"spec.yaml", "behind the camera"}},
      {"FacingAway",
       "    - { id: \"p1\", t: [ 0.0, 0.0, 0.01 ], r: [ 0.0, 1.6, 0.0 ] }\n",
       {"spec.yaml", "behind the camera"}},
  };
  for (const auto& [name, list, message] : lists) {
    const std::string l = list;
    add(
        c, "SimulatePoses" + name,
        [l](Env e) { return "simulate poses --spec " + specWith(e, l) + " -o " + e.p("out"); }, 1, message);
  }
  add(c, "SimulateHugeCamera",
      [](Env e) {
        const std::string camera =
            "%YAML:1.0\n---\nimage_width: 65536\nimage_height: 65536\nmodel: \"opencv\"\n"
            "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
            "   data: [ 420., 0., 32767.5, 0., 420., 32767.5, 0., 0., 1. ]\n"
            "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
            "   data: [ 0., 0., 0., 0., 0. ]\n";
        return "simulate poses --spec " + specWith(e, validPoseList(), camera) + " -o " + e.p("out");
      },
      1, {"65536x65536"});
  add(c, "SimulateCalibrationHugeCamera",
      [](Env e) {
        specWith(e, validPoseList(),
                 "%YAML:1.0\n---\nimage_width: 20000\nimage_height: 20000\nmodel: \"opencv\"\n"
                 "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                 "   data: [ 420., 0., 9999.5, 0., 420., 9999.5, 0., 0., 1. ]\n"
                 "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
                 "   data: [ 0., 0., 0., 0., 0. ]\n");
        return "simulate calibration --spec " + e.p("spec.yaml") + " -o " + e.p("out");
      },
      1, {"20000x20000"});
}

// ---- mire simulate campaign: refused before any rendering ----
void simulateCampaignCases(std::vector<Case>& c) {
  const auto campaign = [](const std::string& extra) {
    return [extra](Env e) { return "simulate campaign -o " + e.p("out") + " " + extra; };
  };
  const std::vector<std::tuple<std::string, std::string, std::vector<std::string>>> options = {
      {"MechanismUnknown", "--mechanism scara", {"--mechanism 'scara'", "valid: h4, delta, gough-stewart"}},
      {"MechanismMissing", "", {"--mechanism"}},
      {"ImagesPerPoseZero", "--mechanism delta --images-per-pose 0", {"--images-per-pose 0", "1 to 100"}},
      {"ImagesPerPoseNegative", "--mechanism delta --images-per-pose -3", {"--images-per-pose"}},
      {"ImagesPerPoseHuge", "--mechanism h4 --images-per-pose 1000", {"--images-per-pose 1000", "1 to 100"}},
      {"ImagesPerPoseText", "--mechanism delta --images-per-pose many", {"--images-per-pose"}},
      {"CalibrationViewsTwo", "--mechanism delta --calibration-views 2", {"--calibration-views 2", "at least 3"}},
      {"SeedNegative", "--mechanism delta --seed -1", {"--seed"}},
  };
  for (const auto& [name, extra, message] : options) add(c, "SimulateCampaign" + name, campaign(extra), 2, message);
  add(c, "SimulateCampaignOutputNotACampaign",
      [](Env e) {
        e.write("mine/notes.txt", "my notes");
        return "simulate campaign --mechanism delta -o " + e.p("mine");
      },
      2, {"mine", "not a previous campaign (no truth/robot.yaml)"});
  add(c, "SimulateCampaignOutputEmpty", [](Env) { return std::string("simulate campaign --mechanism delta -o ''"); }, 2,
      {"-o: empty path"});
  add(c, "SimulateCampaignOutputIsFile",
      [](Env e) { return "simulate campaign --mechanism delta -o " + e.write("plain", "x"); }, 1,
      {"plain", "not a folder"});
}

// ---- the newer commands (fkm, ikm, plan, select, simulate campaign): paths, counts, boards ----
const char* kH4Workspace = "x_m: [-0.1, 0.1]\ny_m: [-0.1, 0.1]\nz_m: [-0.70, -0.55]\ntheta_deg: [-20, 20]\n";

std::string fkm(Env e, const std::string& params, const std::string& joints, const std::string& extra = "") {
  return "fkm --params " + params + " --joints " + joints + " -o " + e.p("out/pred.csv") + " " + extra;
}
std::string ikm(Env e, const std::string& params, const std::string& poses) {
  return "ikm --params " + params + " --poses " + poses + " -o " + e.p("out/commands.csv");
}
std::string plan(Env e, const std::string& workspace, const std::string& extra = "") {
  return "plan --model h4-12 --workspace " + workspace + " --count 15 -o " + e.p("out/plan.csv") + " " + extra;
}
// An identified-parameter file with its covariance side file (the path checks come first: the
// contents are never read by these cases).
std::string paramsWithSide(Env e) {
  e.write("id_covariance.csv", "parameter,R\nR,1e-8\n");
  return e.write("id.yaml", "model: h4-12\n");
}
std::string effectorPoses(Env e) { return e.write("effector.csv", "pose_id,x_m,y_m,z_m,theta_rad\na,0,0,-0.6,0\n"); }

void newerCommandCases(std::vector<Case>& c) {
  struct Input {
    std::string name, option;
    std::function<std::string(Env, const std::string&)> command;
  };
  const std::vector<Input> inputs = {
      {"FkmParams", "--params", [](Env e, const std::string& x) { return fkm(e, x, e.joints_csv()); }},
      {"FkmJoints", "--joints", [](Env e, const std::string& x) { return fkm(e, paramsWithSide(e), x); }},
      {"IkmPoses", "--poses", [](Env e, const std::string& x) { return ikm(e, paramsWithSide(e), x); }},
      {"PlanWorkspace", "--workspace", [](Env e, const std::string& x) { return plan(e, x); }},
      {"SelectPoses", "--poses",
       [](Env e, const std::string& x) { return "select --poses " + x + " --joints " + e.joints_csv(); }},
  };
  for (const Input& input : inputs) {
    const auto command = input.command;
    add(c, input.name + "Fifo", [command](Env e) { return command(e, e.fifo("pipe")); }, 1,
        {input.option, "pipe", "FIFO"});
    add(c, input.name + "Device", [command](Env e) { return command(e, "/dev/zero"); }, 1,
        {input.option, "/dev/zero", "device"});
  }
  // Class 1: an output onto an input's side file.
  add(c, "IkmOutputIsParamsSideFile",
      [](Env e) {
        const std::string params = paramsWithSide(e);
        return "ikm --params " + params + " --poses " + effectorPoses(e) + " -o " + e.p("id_covariance.csv");
      },
      2, {"-o", "id_covariance.csv", "the side file of the input --params", "overwritten"});
  add(c, "FkmCameraSideFileIsParamsSideFile",
      [](Env e) {
        const std::string params = paramsWithSide(e);
        return "fkm --params " + params + " --joints " + e.joints_csv() + " --frame camera -o " + e.p("id.csv");
      },
      2, {"the covariance side file of -o", "the side file of the input --params"});
  add(c, "SimulateCampaignRerunKeepsUserFiles",
      [](Env e) {
        e.write("previous/truth/robot.yaml", "# a previous campaign\n");
        e.write("previous/my_notes.txt", "my notes");
        return "simulate campaign --mechanism delta -o " + e.p("previous");
      },
      2, {"previous", "my_notes.txt", "mire did not write", "would delete them"});
  // Class 3: counts bounded before any work.
  add(c, "PlanCandidatesBillion",
      [](Env e) { return plan(e, e.write("workspace.yaml", kH4Workspace), "--candidates 1000000000"); }, 2,
      {"--candidates 1000000000", "at most 100000"});
  add(c, "PlanCameraHugeBoard",
      [](Env e) {
        const std::string board =
            e.write("target.yaml", "%YAML:1.0\n---\ntype: chessboard\ncols: 400\nrows: 300\nsquare_size_m: 0.001\n");
        return plan(e, e.write("workspace.yaml", kH4Workspace), "--camera " + e.camera() + " --target " + board);
      },
      1, {"target.yaml", "120000 features", "at most 20000"});
  add(c, "PlanCameraImplausibleCamera",
      [](Env e) {
        return plan(e, e.write("workspace.yaml", kH4Workspace),
                    "--camera " + cameraFile(e, "420., 0., -5000., 0., 420., 179.5, 0., 0., 1.", kD) + " --target " +
                        e.target());
      },
      1, {"camera.yaml", "principal point"});
  // Class 4: absurd values accepted before.
  add(c, "PlanCameraK1Hundred",
      [](Env e) {
        return plan(e, e.write("workspace.yaml", kH4Workspace),
                    "--camera " + cameraFile(e, kK, "100., 0.02, 0., 0., 0.") + " --target " + e.target());
      },
      1, {"camera.yaml", "stretches the image corner"});
  add(c, "PlanPixelSigmaZero",
      [](Env e) {
        return plan(e, e.write("workspace.yaml", kH4Workspace),
                    "--camera " + e.camera() + " --target " + e.target() + " --pixel-sigma 0");
      },
      2, {"--pixel-sigma 0", "never 0"});
  add(c, "CalibrateImageSizeZero",
      [](Env e) {
        return "calibrate --target " + e.cal_target() + " --detections " + e.write("det.csv", "x\n") +
               " --image-size 0 0 -o " + e.p("out/camera.yaml");
      },
      2, {"--image-size", "WIDTH HEIGHT"});
  add(c, "CalibrateFixEveryParameter",
      [](Env e) { return calibrate(e, e.cal_target(), e.images(), "--model pinhole --fix fx,fy,cx,cy"); }, 1,
      {"every parameter", "no free parameter"});
  add(c, "CalibrateSameImageTwice",
      [](Env e) {
        return calibrate(e, e.cal_target(), imagesWith(e, "view_100.png", slurp(e.f.cal / "images/view_000.png")));
      },
      1, {"view_100.png", "exactly the detections of view_000.png", "same image twice"});
  add(c, "IdentifyDeltaOnH4Joints", [](Env e) { return identifyDefault(e, "--model delta"); }, 1,
      {"joints.csv", "q4_rad", "another mechanism"});
  add(c, "SelectDeltaModelsOnH4Joints",
      [](Env e) {
        return "select --poses " + e.poses_csv() + " --joints " + e.joints_csv() + " --models delta,delta-legs";
      },
      1, {"joints.csv", "q4_rad", "another mechanism"});
  add(c, "IkmThetaInDegrees",
      [](Env e) {
        const std::string params = e.copy(test::sourceDir() / "datasets/specs/h4_nominal.yaml", "nominal.yaml");
        return ikm(e, params, e.write("effector.csv", "pose_id,x_m,y_m,z_m,theta_rad\na,0,0,-0.6,20\n"));
      },
      1, {"effector.csv:2", "theta_rad = 20", "degrees"});
  add(c, "FkmHexapodJointsOutOfStroke",
      [](Env e) {
        // The nominal hexapod as a parameter file (its legs' stroke is about ±0.1 m around 0.05).
        std::string params = mechanism::parameterFileString(mechanism::makeRegisteredModel("gough-stewart").nominal, {},
                                                            {{"model", "gough-stewart"}});
        for (const std::string& name :
             mechanism::ExternalParameterization(mechanism::ExternalForm::Full).parameters().names())
          params += name + ": 0\n";
        return fkm(e, e.write("gs.yaml", params),
                   e.write("joints.csv", "pose_id,q1_m,q2_m,q3_m,q4_m,q5_m,q6_m\na,0.5,0.5,0.5,0.5,0.5,0.5\n"));
      },
      1, {"joints.csv:2", "pose 'a'", "outside their stroke", "1 (0.5 m)"});
  add(c, "FkmJointsInDegrees",
      [](Env e) {
        const std::string params = e.copy(test::sourceDir() / "datasets/specs/h4_nominal.yaml", "nominal.yaml");
        return fkm(e, params, e.write("joints.csv", "pose_id,q1_rad,q2_rad,q3_rad,q4_rad\na,10,20,30,40\n"));
      },
      1, {"joints.csv:2", "q1_rad = 10", "degrees"});
  add(c, "CovarianceSideNotPositiveNamesFile",
      [](Env e) {
        std::string text = "pose_id,part,row,tx,ty,tz,rx,ry,rz\n";
        for (const char* axis : {"tx", "ty", "tz", "rx", "ry", "rz"})
          text += std::string("1,total,") + axis + ",0,0,0,0,0,0\n";  // a zero covariance
        return identifyDefault(e, "--pose-covariances " + e.write("cov.csv", text));
      },
      1, {"cov.csv", "pose '1'", "not positive definite"});
  add(c, "PlanOnePointWorkspace",
      [](Env e) {
        return plan(e, e.write("workspace.yaml", "x_m: [0, 0]\ny_m: [0, 0]\nz_m: [-0.6, -0.6]\ntheta_deg: [0, 0]\n"));
      },
      1, {"workspace.yaml", "single point"});
  add(c, "FkmJointsHuge",
      [](Env e) {
        const std::string params = e.copy(test::sourceDir() / "datasets/specs/h4_nominal.yaml", "nominal.yaml");
        return fkm(e, params, e.write("joints.csv", "pose_id,q1_rad,q2_rad,q3_rad,q4_rad\na,1e308,0.3,0.3,0.3\n"));
      },
      1, {"joints.csv:2", "q1_rad = 1e+308", "degrees"});
  add(c, "SelectOnOnePoseRepeated",
      [](Env e) {
        // Twelve copies of the campaign's first pose (and its joints), under distinct ids.
        const auto firstRowTwelveTimes = [](const std::string& text) {
          std::stringstream in(text);
          std::string header, row, out;
          std::getline(in, header);
          std::getline(in, row);
          out = header + "\n";
          for (int k = 1; k <= 12; ++k) out += "r" + std::to_string(k) + row.substr(row.find(',')) + "\n";
          return out;
        };
        const std::string poses = e.write("poses.csv", firstRowTwelveTimes(slurp(e.f.campaign / "poses.csv")));
        const std::string joints = e.write("joints.csv", firstRowTwelveTimes(slurp(e.f.campaign / "joints.csv")));
        return "select --poses " + poses + " --joints " + joints;
      },
      1, {"poses.csv", "no candidate model could be identified on these 12 poses", "repeat one another"});
  // Class 4: an empty model list is not the default list.
  add(c, "SelectModelsEmpty",
      [](Env e) { return "select --poses " + e.poses_csv() + " --joints " + e.joints_csv() + " --models ''"; }, 2,
      {"--models", "empty"});
  // An H4 parameter file handed to the simulated Delta: 4 joints for 3.
  add(c, "SimulateIso9283ParamsOfAnotherRobot",
      [](Env e) {
        const std::string params = e.copy(test::sourceDir() / "datasets/specs/h4_nominal.yaml", "nominal.yaml");
        return "simulate iso9283 --mechanism delta --params " + params + " -o " + e.p("after");
      },
      1, {"nominal.yaml", "joints that are not those of the simulated delta"});
  add(c, "SimulateIso9283UnknownMechanism",
      [](Env e) {
        const std::string params = e.copy(test::sourceDir() / "datasets/specs/h4_nominal.yaml", "nominal.yaml");
        return "simulate iso9283 --mechanism deltaa --params " + params + " -o " + e.p("after");
      },
      2, {"--mechanism 'deltaa'", "unknown mechanism"});
  add(c, "SelectMountingUnknown",
      [](Env e) { return "select --poses " + e.poses_csv() + " --joints " + e.joints_csv() + " --mounting eye-in-hand"; },
      2, {"--mounting 'eye-in-hand'", "camera-on-effector"});
  add(c, "PlanMountingUnknown",
      [](Env e) { return plan(e, e.write("workspace.yaml", kH4Workspace), "--mounting eye-in-hand"); }, 2,
      {"--mounting 'eye-in-hand'", "camera-on-effector"});
  // The H4's models assume the camera fixed (paper §4): refused by name, as identify and select do.
  add(c, "PlanMountingOnEffectorH4",
      [](Env e) { return plan(e, e.write("workspace.yaml", kH4Workspace), "--mounting camera-on-effector"); }, 2,
      {"--mounting camera-on-effector", "h4-12", "assumes the camera fixed"});
  add(c, "DemoMountingUnknown", [](Env e) { return "demo --mechanism delta --mounting eye-in-hand -o " + e.p("demo"); },
      2, {"--mounting 'eye-in-hand'", "camera-on-effector"});
  add(c, "DemoMountingOnEffectorH4", [](Env e) { return "demo --mounting camera-on-effector -o " + e.p("demo"); }, 2,
      {"--mounting camera-on-effector", "H4 demo", "assume the camera fixed"});
}

// ---- class 4, absurd input accepted: a robust fit on joints of no robot, a negative length, an
// edited mounting beside its side file, a tag family read on another family's tags ----

// `mire <arguments>` run while a case prepares its inputs (before the snapshot); "" when it succeeded.
std::string prepareWithMire(const std::string& arguments) {
  int code = -1;
  const std::string output = test::captureCommand(test::mireBinary().string() + " " + arguments + " </dev/null", &code);
  return code == 0 ? "" : "\n# PREPARATION FAILED: mire " + arguments + "\n" + output;
}

// The campaign's joints.csv with every reading moved by a pseudo-random offset in ±amplitude
// (reproducible: a hash of the row and column), i.e. joints that belong to none of the poses.
std::string scrambledJoints(Env e, double amplitude) {
  std::stringstream in(slurp(e.f.campaign / "joints.csv"));
  std::string line, out;
  std::getline(in, line);
  out = line + "\n";
  for (int row = 0; std::getline(in, line); ++row) {
    std::stringstream cells(line);
    std::string cell;
    std::getline(cells, cell, ',');
    out += cell;
    for (int column = 0; std::getline(cells, cell, ','); ++column) {
      const double hash = std::sin(12.9898 * (4 * row + column + 1)) * 43758.5453;
      out += "," + std::to_string(std::stod(cell) + amplitude * (2.0 * (hash - std::floor(hash)) - 1.0));
    }
    out += "\n";
  }
  return e.write("joints.csv", out);
}

// An identified H4 file (id.yaml + id_covariance.csv, from the campaign) with one line edited.
std::string identifiedWithEdit(Env e, const std::string& key, const std::string& value) {
  const std::string failed =
      prepareWithMire("identify --poses " + e.poses_csv() + " --joints " + e.joints_csv() + " -o " + e.p("id.yaml"));
  std::stringstream in(slurp(e.dir / "id.yaml"));
  std::string line, out;
  while (std::getline(in, line)) out += (line.rfind(key + ":", 0) == 0 ? key + ": " + value : line) + "\n";
  return e.write("id.yaml", out + failed);
}

// tag36h11 images (2 poses, or 4 calibration views) rendered in the case folder; `kind` is
// "poses" or "calibration".
void renderTag36h11(Env e, const std::string& kind) {
  e.write("camera.yaml", slurp(e.f.root / "specs/camera.yaml"));
  e.write("target.yaml",
          "%YAML:1.0\n---\ntype: apriltag\ncols: 3\nrows: 2\nfamily: tag36h11\n"
          "tag_size_m: 0.05\ntag_spacing_m: 0.065\nfirst_id: 0\n");
  const std::string block = kind == "poses"
                                ? "poses:\n  images_per_pose: 1\n  list:\n"
                                  "    - { id: \"p1\", t: [ -0.08, -0.05, 0.4 ], r: [ 0.0, 0.0, 0.0 ] }\n"
                                  "    - { id: \"p2\", t: [ -0.07, -0.04, 0.45 ], r: [ 0.2, 0.1, 0.0 ] }\n"
                                : "calibration:\n  views: 4\n  distance_m: [ 0.35, 0.45 ]\n  max_tilt_deg: 25\n";
  const std::string spec = e.write("spec.yaml",
                                   "%YAML:1.0\n---\ncamera: \"camera.yaml\"\ntarget: \"target.yaml\"\n"
                                   "seed: 4\nrender:\n  supersampling: 2\nnoise:\n  gaussian_sigma: 2.0\n" +
                                       block);
  const std::string failed = prepareWithMire("simulate " + kind + " --spec " + spec + " -o " + e.p("sim"));
  e.write("tag16h5.yaml",
          "%YAML:1.0\n---\ntype: apriltag\ncols: 3\nrows: 2\nfamily: tag16h5\n"
          "tag_size_m: 0.05\ntag_spacing_m: 0.065\nfirst_id: 0\n" +
              failed);
}

void class4Cases(std::vector<Case>& c) {
  add(c, "IdentifyRobustJointsOfNoRobot",
      [](Env e) { return identify(e, e.poses_csv(), scrambledJoints(e, 0.05), "--robust"); }, 1,
      {"poses.csv with {dir}/joints.csv", "the robust fit gave up most poses", "more than half",
       "do not describe one robot"});
  add(c, "NominalNegativeLength",
      [](Env e) {
        return identifyDefault(e, "--nominal " + e.edit(test::sourceDir() / "datasets/specs/h4_nominal.yaml",
                                                        "nominal.yaml", "L: 0.30 ", "L: -0.29 "));
      },
      1, {"nominal.yaml:5: L = -0.29 m: a length must be positive"});
  add(c, "FkmParamsNegativeLength",
      [](Env e) {
        return fkm(e, e.edit(test::sourceDir() / "datasets/specs/h4_nominal.yaml", "id.yaml", "L: 0.30 ", "L: -0.29 "),
                   e.joints_csv());
      },
      1, {"id.yaml:5: L = -0.29 m: a length must be positive"});
  add(c, "IkmParamsZeroForearm",
      [](Env e) {
        return ikm(e, e.edit(test::sourceDir() / "datasets/specs/h4_nominal.yaml", "id.yaml", "l: 0.70 ", "l: 0 "),
                   effectorPoses(e));
      },
      1, {"id.yaml:6: l = 0 m: a length must be positive"});
  add(c, "FkmCameraMountingEditedBesideSideFile",
      [](Env e) { return fkm(e, identifiedWithEdit(e, "z_BC", "-1e9"), e.joints_csv(), "--frame camera"); }, 1,
      {"id.yaml:", "z_BC = -1e+09 m", "id_covariance.csv", "do not belong together"});
  add(c, "MeasureTag16h5OnTag36h11Images",
      [](Env e) {
        renderTag36h11(e, "poses");
        return measure(e, e.p("sim/camera.yaml"), e.p("tag16h5.yaml"), e.p("sim/poses"));
      },
      1, {"decoded exactly", "another tag family", "no pose could be measured"});
  add(c, "CalibrateTag16h5OnTag36h11Images",
      [](Env e) {
        renderTag36h11(e, "calibration");
        return calibrate(e, e.p("tag16h5.yaml"), e.p("sim/images"));
      },
      1, {"decoded exactly", "another tag family"});
}

// ---- mire measure --legs: legs.yaml, the model, a leg the camera cannot see ----
std::string measureLegs(Env e, const std::string& legs_yaml) {
  // The nominal hexapod's joints at its reference pose, one row per pose folder of the fixture.
  const mechanism::RegisteredModel model = mechanism::makeRegisteredModel("gough-stewart");
  const Eigen::VectorXd geometric = model.nominal.values();
  const Eigen::VectorXd q =
      model.mechanism
          ->inverseKinematics(geometric, model.mechanism->poseToTransform(model.mechanism->referencePose(geometric)))
          .joints;
  std::string joints = "pose_id";
  for (const std::string& column : model.mechanism->jointColumnNames()) joints += "," + column;
  for (const auto& entry : fs::directory_iterator(e.poses_dir())) {
    joints += "\n" + entry.path().filename().string();
    for (Eigen::Index i = 0; i < q.size(); ++i) joints += "," + std::to_string(q[i]);
  }
  return "measure --camera " + e.camera() + " --legs " + e.write("legs.yaml", legs_yaml) + " --joints " +
         e.write("joints.csv", joints + "\n") + " --poses " + e.poses_dir() + " -o " + e.p("out/legs.csv");
}

void legMeasureCases(std::vector<Case>& c) {
  const std::string placement = "base_T_camera:\n  t_mm: [0, 0, 1500]\n  r_deg: [180, 0, 0]\n";
  add(c, "LegsYamlMissingRadius", [placement](Env e) { return measureLegs(e, "model: gough-stewart\n" + placement); },
      1, {"legs.yaml", "missing key 'radius_mm'"});
  add(c, "LegsYamlModelWithoutLegs",
      [placement](Env e) { return measureLegs(e, "model: h4-12\nradius_mm: 8\n" + placement); }, 1,
      {"legs.yaml:1", "'model'", "h4-12", "no observable legs"});
  add(c, "LegsOutsideTheImage",
      [](Env e) {
        return measureLegs(
            e, "model: gough-stewart\nradius_mm: 8\nbase_T_camera:\n  t_mm: [0, 0, 5000]\n  r_deg: [0, 0, 0]\n");
      },
      1, {"leg 1 not measured", "behind the camera", "no leg could be measured"});
  add(c, "LegsWithTarget",
      [placement](Env e) {
        return measureLegs(e, "model: gough-stewart\nradius_mm: 8\n" + placement) + " --target " + e.target();
      },
      2, {"--legs measures the legs only"});
  add(c, "LegsWithoutJoints",
      [](Env e) {
        return "measure --camera " + e.camera() + " --legs " + e.write("legs.yaml", "model: delta\n") + " --poses " +
               e.poses_dir() + " -o " + e.p("out/legs.csv");
      },
      2, {"--legs needs --joints"});
}

std::vector<Case> makeCases() {
  std::vector<Case> cases;
  inputCases(cases);
  outputCases(cases);
  optionCases(cases);
  cameraTargetCases(cases);
  imageCases(cases);
  csvCases(cases);
  specCases(cases);
  simulateCampaignCases(cases);
  newerCommandCases(cases);
  class4Cases(cases);
  legMeasureCases(cases);
  return cases;
}

}  // namespace

const std::vector<Case>& allCases() {
  static const std::vector<Case> cases = makeCases();
  return cases;
}

}  // namespace mire::app::badinput
