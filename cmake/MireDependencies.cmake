# Every dependency comes from Debian's packages (scripts/setup.sh installs them). Modules link the
# imported targets of the components they use (doc/install.md "Dependencies"); imported targets'
# headers are SYSTEM, so warnings (and MIRE_WERROR) apply to mire's own code only.
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs calib3d aruco)
find_package(VISP REQUIRED COMPONENTS visp_core visp_vision)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Ceres REQUIRED)
find_package(Threads REQUIRED)
find_package(CLI11 REQUIRED)
find_package(apriltag REQUIRED CONFIG)
# apps only (report.json, doc/report-json.md): header-only, not part of any library's interface.
find_package(nlohmann_json 3 REQUIRED)
