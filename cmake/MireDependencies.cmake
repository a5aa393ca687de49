# Every dependency comes from Debian's packages (scripts/setup.sh installs them).
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs calib3d features2d aruco)
find_package(VISP REQUIRED COMPONENTS visp_core visp_vision visp_blob visp_io)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Ceres REQUIRED)
find_package(Threads REQUIRED)
find_package(CLI11 REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(APRILTAG REQUIRED IMPORTED_TARGET apriltag)

# ViSP exports plain variables; wrap them in a target whose headers are SYSTEM so that
# -Werror applies to mire's code only.
add_library(mire_visp INTERFACE)
target_include_directories(mire_visp SYSTEM INTERFACE ${VISP_INCLUDE_DIRS})
target_link_libraries(mire_visp INTERFACE ${VISP_LIBRARIES})
add_library(mire_opencv INTERFACE)
target_include_directories(mire_opencv SYSTEM INTERFACE ${OpenCV_INCLUDE_DIRS})
target_link_libraries(mire_opencv INTERFACE ${OpenCV_LIBS})
