# A fresh build's time goes into parsing and instantiating the same headers
# (Eigen, fmt, nlohmann::json, CLI11, Ceres) in every source file. A unity
# build compiles each target's sources in batches of 8 as one file, so that
# what they share is instantiated once per batch: a fresh build of the
# command in half the time (docs/development.md), the same object code.
# Helpers in anonymous namespaces must then have names unique within their
# target; CI builds this way, so a clash is caught there. The scan
# readers keep their own files (each format's layout constants share
# names). Turn it off for quick rebuilds of one file while developing (the
# dev preset does).
option(WEARSCAR_UNITY "Compile each target's sources in batches (unity build)" ON)
if(WEARSCAR_UNITY)
  set(CMAKE_UNITY_BUILD ON)
endif()

# A compiler cache: a clean clone on a machine that has built wearscar
# before (CI's, a developer's second checkout) reuses the objects. Paths
# under the source tree are hashed relative to it (CCACHE_BASEDIR), so two
# checkouts in different folders share their entries.
option(WEARSCAR_CCACHE "Compile through ccache when it is installed" ON)
if(WEARSCAR_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(WEARSCAR_CCACHE_PROGRAM ccache)
  if(WEARSCAR_CCACHE_PROGRAM)
    set(CMAKE_CXX_COMPILER_LAUNCHER
        ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${PROJECT_SOURCE_DIR}
        CCACHE_NOHASHDIR=true ${WEARSCAR_CCACHE_PROGRAM})
  endif()
endif()
# __FILE__ (in WEARSCAR_CHECK's messages) names a source relative to the
# source tree, so an object does not carry the folder it was built in: the
# same cache entry then serves every checkout.
add_compile_options(-fmacro-prefix-map=${PROJECT_SOURCE_DIR}/=)
