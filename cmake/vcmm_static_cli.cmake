# vcmm_static_cli.cmake — link the `vcmm` command as a static PIE (VCMM_STATIC_CLI).
#
# Why: one roundness evaluation of a 3 600-point profile costs well under a millisecond in
# the library; a dynamically linked process spends about as long again in the loader
# (symbol lookup and relocation for libstdc++, GMP, MPFR) and in page faults
# (docs/performance.md). A static PIE skips the loader, and unlike a plain -static binary it
# keeps the PT_GNU_EH_FRAME lookup, so the first exception (every error path, --version,
# --help) costs microseconds instead of a ~2 ms sort of all unwind entries.
#
# How: CGAL's imported target names GMP, MPFR and gmpxx by the path of their shared objects,
# which a static link cannot use. Where the archives sit beside them, those paths are
# replaced by plain library names plus their directory: every other target still links the
# shared objects exactly as before (the linker prefers .so), and the command, linked with
# -static-pie, picks the archives. Sets VCMM_STATIC_CLI_ACTIVE when all of this applies.
set(VCMM_STATIC_CLI_ACTIVE OFF)
if(NOT VCMM_STATIC_CLI OR VCMM_SANITIZE OR VCMM_FUZZ OR NOT TARGET CGAL::CGAL)
  return()
endif()

include(CheckCXXSourceCompiles)
set(CMAKE_REQUIRED_LINK_OPTIONS -static-pie)
set(CMAKE_REQUIRED_FLAGS -fPIE)
check_cxx_source_compiles("#include <string>\nint main() { return static_cast<int>(std::string(\"x\").size()) - 1; }"
                          VCMM_HAVE_STATIC_PIE)
unset(CMAKE_REQUIRED_LINK_OPTIONS)
unset(CMAKE_REQUIRED_FLAGS)
if(NOT VCMM_HAVE_STATIC_PIE)
  message(STATUS "vcmm: the toolchain cannot link a static PIE; the vcmm command is linked dynamically")
  return()
endif()

# CGAL::CGAL is an alias of the imported target that holds the properties.
get_target_property(_vcmm_cgal CGAL::CGAL ALIASED_TARGET)
if(NOT _vcmm_cgal)
  set(_vcmm_cgal CGAL::CGAL)
endif()
get_target_property(_vcmm_cgal_libs ${_vcmm_cgal} INTERFACE_LINK_LIBRARIES)
set(_vcmm_new_libs)
set(_vcmm_dirs)
foreach(_lib IN LISTS _vcmm_cgal_libs)
  if(_lib MATCHES "^(.*)/lib([A-Za-z0-9_+]+)\\.so$")
    set(_dir "${CMAKE_MATCH_1}")
    set(_name "${CMAKE_MATCH_2}")
    if(NOT EXISTS "${_dir}/lib${_name}.a")
      message(STATUS "vcmm: no ${_dir}/lib${_name}.a; the vcmm command is linked dynamically")
      return()
    endif()
    list(APPEND _vcmm_new_libs "${_name}")
    list(APPEND _vcmm_dirs "${_dir}")
  else()
    list(APPEND _vcmm_new_libs "${_lib}")
  endif()
endforeach()
list(REMOVE_DUPLICATES _vcmm_dirs)
set_target_properties(${_vcmm_cgal} PROPERTIES INTERFACE_LINK_LIBRARIES "${_vcmm_new_libs}")
set_property(TARGET ${_vcmm_cgal} APPEND PROPERTY INTERFACE_LINK_DIRECTORIES ${_vcmm_dirs})
set(VCMM_STATIC_CLI_ACTIVE ON)
