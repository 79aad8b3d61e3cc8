# One static library per module of src/, with its dependencies declared, so that an include that runs
# back up the layers fails to build: a module's headers are visible only through its own include root,
# build/module_includes/<name>/, which holds a link <dir> -> src/<dir> and links to the public headers
# (include/mesodpd/) that the module implements. A target sees the roots of the modules it links.
#
#   mesodpd_module(<target> DIR <dir> [SOURCES ...] [DEPENDS <targets> ...] [PUBLIC_HEADERS <names> ...])
#
# A module without sources (physics: header-only laws) is an INTERFACE library. The layers and their
# order are in docs/architecture.md.
set(MESODPD_MODULE_TARGETS "" CACHE INTERNAL "")

function(mesodpd_module target)
  cmake_parse_arguments(M "" "DIR" "SOURCES;DEPENDS;PUBLIC_HEADERS" ${ARGN})
  set(root ${PROJECT_BINARY_DIR}/module_includes/${target})
  file(REMOVE_RECURSE ${root})
  file(MAKE_DIRECTORY ${root}/mesodpd)
  file(CREATE_LINK ${PROJECT_SOURCE_DIR}/src/${M_DIR} ${root}/${M_DIR} SYMBOLIC)
  foreach(h IN LISTS M_PUBLIC_HEADERS)
    if(NOT EXISTS ${PROJECT_SOURCE_DIR}/include/mesodpd/${h})
      message(FATAL_ERROR "mesodpd_module(${target}): no include/mesodpd/${h}")
    endif()
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/include/mesodpd/${h} ${root}/mesodpd/${h} SYMBOLIC)
  endforeach()
  if(M_SOURCES)
    add_library(${target} STATIC ${M_SOURCES})
    set(scope PUBLIC)
  else()
    add_library(${target} INTERFACE)
    set(scope INTERFACE)
  endif()
  target_include_directories(${target} ${scope} $<BUILD_INTERFACE:${root}> $<INSTALL_INTERFACE:include>)
  target_link_libraries(${target} ${scope} mesodpd_options ${M_DEPENDS})
  set(MESODPD_MODULE_TARGETS ${MESODPD_MODULE_TARGETS} ${target} CACHE INTERNAL "")
endfunction()
