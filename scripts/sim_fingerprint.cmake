# Writes OUT (a C header defining MCREF_SIM_FINGERPRINT) from the sources of SRC
# that determine what a simulation computes, at every build, touching it only
# when the fingerprint changes. `validate` reuses cached tables only when their
# stored fingerprint equals the binary's (validate/suite.cpp).
#
# The fingerprint is the first 16 hex digits of a SHA-256 over
#   - every file under sim/, and every file they include with #include "...",
#     transitively (e.g. models/core/rng.h, models/sggx/sggx_distribution.h),
#     each header with the .cpp beside it; by relative path and content;
#   - BUILD: the mcref version, compiler, flags and library versions (CMakeLists.txt).
# Files that sim/ does not reach (validate/, the report, the analytic models
# only validate uses, scripts/, tests/) are not part of it; nor is the git commit.
# Usage: cmake -DSRC=<source dir> -DOUT=<header> -DBUILD=<text> [-DMANIFEST=<file>] -P sim_fingerprint.cmake
cmake_minimum_required(VERSION 3.20)
file(GLOB_RECURSE queue LIST_DIRECTORIES false RELATIVE ${SRC} ${SRC}/sim/*)
list(SORT queue)
set(seen ${queue})
while(queue)
  list(POP_FRONT queue file)
  get_filename_component(dir ${file} DIRECTORY)
  file(STRINGS ${SRC}/${file} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" inc "${line}")
    # Project includes are relative to the source root, or else to the file's folder.
    set(found "")
    foreach(candidate ${inc} ${dir}/${inc})
      if(NOT found AND EXISTS ${SRC}/${candidate} AND NOT IS_DIRECTORY ${SRC}/${candidate})
        file(RELATIVE_PATH found ${SRC} ${SRC}/${candidate})
      endif()
    endforeach()
    if(NOT found)
      continue()  # a system or generated header (mcref_commit.h)
    endif()
    set(new ${found})
    string(REGEX REPLACE "\\.h$" ".cpp" impl ${found})
    if(NOT impl STREQUAL found AND EXISTS ${SRC}/${impl})
      list(APPEND new ${impl})
    endif()
    foreach(f ${new})
      if(NOT f IN_LIST seen)
        list(APPEND seen ${f})
        list(APPEND queue ${f})
      endif()
    endforeach()
  endforeach()
endwhile()
list(SORT seen)
set(manifest "")
foreach(f ${seen})
  file(SHA256 ${SRC}/${f} h)
  string(APPEND manifest "${f} ${h}\n")
endforeach()
string(APPEND manifest "build: ${BUILD}\n")
if(MANIFEST)
  file(WRITE ${MANIFEST} "${manifest}")  # what went in, for tests and curious users
endif()
string(SHA256 digest "${manifest}")
string(SUBSTRING ${digest} 0 16 fingerprint)
set(text "#pragma once\n#define MCREF_SIM_FINGERPRINT \"${fingerprint}\"\n")
include(${CMAKE_CURRENT_LIST_DIR}/write_if_changed.cmake)
write_if_changed(${OUT} "${text}")
