# SPDX-License-Identifier: Apache-2.0
# Every dependency is a Debian 12 package; scripts/install-deps.sh installs them.
# OpenVDB ships only FindOpenVDB.cmake, in <libdir>/cmake/OpenVDB.
foreach(dir /usr/lib/x86_64-linux-gnu/cmake/OpenVDB /usr/lib/cmake/OpenVDB /usr/local/lib/cmake/OpenVDB)
    if(EXISTS ${dir}/FindOpenVDB.cmake)
        list(APPEND CMAKE_MODULE_PATH ${dir})
    endif()
endforeach()

find_package(Threads REQUIRED)
find_package(TBB REQUIRED)
find_package(Imath REQUIRED)
find_package(OpenVDB REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(OpenMesh REQUIRED)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs)
find_package(yaml-cpp REQUIRED)
find_package(embree 3 REQUIRED)
find_package(spdlog REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
