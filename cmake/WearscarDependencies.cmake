# All dependencies come from Debian 12 packages (scripts/install-deps).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Ceres 2.1 REQUIRED)
# imgcodecs is not linked: it pulls ~140 libraries (GDAL, ...) into every
# process; PNGs are written with libpng.
find_package(OpenCV 4.6 REQUIRED COMPONENTS core imgproc photo)
# Only what scan/src/level.cc uses (a component that pulls VTK fails
# Debian's PCL config).
find_package(PCL 1.13 REQUIRED COMPONENTS common sample_consensus)
find_package(fmt REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(LIBZIP REQUIRED IMPORTED_TARGET libzip)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)
pkg_check_modules(LIBPNG REQUIRED IMPORTED_TARGET libpng)
pkg_check_modules(XLSXWRITER REQUIRED IMPORTED_TARGET xlsxwriter)
# The periodic-line search's spectra (Debian's libfftw3-dev, its single
# precision): 2.5x Eigen's kissfft on 2^18-sample windows in double, twice
# that in single.
pkg_check_modules(FFTW3F REQUIRED IMPORTED_TARGET fftw3f)
# The live page of `wearscar watch` (Debian's libcpp-httplib-dev).
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
find_package(pugixml REQUIRED)
find_package(ZLIB REQUIRED)
find_package(OpenSSL 3 REQUIRED COMPONENTS Crypto)

# fast_float is header-only; Debian ships the header without a CMake config.
find_path(FASTFLOAT_INCLUDE_DIR fast_float/fast_float.h REQUIRED)
add_library(wearscar_fast_float INTERFACE)
target_include_directories(wearscar_fast_float SYSTEM INTERFACE ${FASTFLOAT_INCLUDE_DIR})

# PCL exports include dirs and definitions as variables, not a target.
# The RANSAC plane is compiled from PCL's headers (PCL_NO_PRECOMPILE in
# scan/src/level.cc) instead of linking libpcl_sample_consensus: its
# 16,700 symbol bindings, made at every start of the command, were 10 ms
# of a 22 ms `wearscar --version` and most of the dynamic loader's work.
set(wearscar_pcl_libraries ${PCL_LIBRARIES})
list(FILTER wearscar_pcl_libraries EXCLUDE REGEX "sample_consensus")
add_library(wearscar_pcl INTERFACE)
target_include_directories(wearscar_pcl SYSTEM INTERFACE ${PCL_INCLUDE_DIRS})
target_link_libraries(wearscar_pcl INTERFACE ${wearscar_pcl_libraries})
target_compile_definitions(wearscar_pcl INTERFACE ${PCL_DEFINITIONS})

if(WEARSCAR_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(WEARSCAR_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

# The command's allocator: mimalloc, which keeps the large blocks a test's
# analysis allocates and frees again and again (glibc's malloc maps and
# unmaps each anew; docs/performance.md). Only the command links it (a
# library must not choose its users' allocator), and never under
# sanitizers, which bring their own.
option(WEARSCAR_MIMALLOC "Link the wearscar command with mimalloc" ${wearscar_uninstrumented})
if(WEARSCAR_MIMALLOC)
  find_package(mimalloc 2 REQUIRED)
endif()
