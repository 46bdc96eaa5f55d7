# find_package(tumble-lcmtypes): the C++ headers of tumble's LCM messages as
# the target tumble::lcmtypes, which brings lcm's headers and library along.
# Installed in <prefix>/share/cmake/tumble-lcmtypes.
get_filename_component(_tumble_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
find_package(PkgConfig REQUIRED)
pkg_check_modules(TUMBLE_LCM REQUIRED IMPORTED_TARGET lcm)
if(NOT TARGET tumble::lcmtypes)
  add_library(tumble::lcmtypes INTERFACE IMPORTED)
  set_target_properties(tumble::lcmtypes PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_tumble_prefix}/include"
    INTERFACE_LINK_LIBRARIES PkgConfig::TUMBLE_LCM)
endif()
unset(_tumble_prefix)
