# The layering check: every rigsim library, executable and test may include (`#include "dir/x.h"`,
# written from the repository root) only headers of its own folder and of the folders whose
# libraries it links, directly or through their PUBLIC and INTERFACE links. The include path is
# the repository root for everything (rigsim_root), so without this check any target could
# include any folder and build by accident of what its libraries happen to link.
#
# Folder <dir> is the library rigsim_<dir> ("/" -> "_"). Scanned: each target's sources, and the
# headers of its own folder that they include (those are the target's too). Headers of other
# folders are that folder's business. A target that links a module left out of this configuration
# (RIGSIM_SKIP_MODULES) is not checked: it cannot be built here either.
#
# The test toolkit, testing/ (rigsim_testing), exists only with RIGSIM_BUILD_TESTS: only tests
# (add_unit_test marks them RIGSIM_TEST) may link it; a library or program that did would not
# build without the tests.
#
# rigsim_check_layers() fails the configuration with one line per include or link that breaks
# these rules.

# Quoted includes of `file` that name a file of the repository.
function(_rigsim_includes_of file out)
  get_property(known GLOBAL PROPERTY "_RIGSIM_INCLUDES_${file}" SET)
  if(known)
    get_property(includes GLOBAL PROPERTY "_RIGSIM_INCLUDES_${file}")
    set(${out} "${includes}" PARENT_SCOPE)
    return()
  endif()
  set(includes "")
  file(STRINGS "${file}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"[^\"]+\"")
  foreach(line IN LISTS lines)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*$" "\\1" included "${line}")
    if(EXISTS "${PROJECT_SOURCE_DIR}/${included}")
      list(APPEND includes "${included}")
    endif()
  endforeach()
  set_property(GLOBAL PROPERTY "_RIGSIM_INCLUDES_${file}" "${includes}")
  set(${out} "${includes}" PARENT_SCOPE)
endfunction()

# Every library `target` links, directly and through PUBLIC/INTERFACE links (LINK_ONLY entries,
# a static library's private links, give no headers and are left out). `complete` is FALSE when a
# rigsim_* library among them is not defined in this configuration.
function(_rigsim_link_closure target out complete)
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "INTERFACE_LIBRARY")
    get_target_property(queue ${target} INTERFACE_LINK_LIBRARIES)
  else()
    get_target_property(queue ${target} LINK_LIBRARIES)
  endif()
  set(closure "")
  set(all_defined TRUE)
  while(queue)
    list(POP_FRONT queue item)
    if(NOT item OR item MATCHES "^\\$<" OR item MATCHES "^::@" OR item IN_LIST closure)
      continue()
    endif()
    list(APPEND closure "${item}")
    if(TARGET ${item})
      get_target_property(next ${item} INTERFACE_LINK_LIBRARIES)
      if(next)
        list(APPEND queue ${next})
      endif()
    elseif(item MATCHES "^rigsim_")
      set(all_defined FALSE)
    endif()
  endwhile()
  set(${out} "${closure}" PARENT_SCOPE)
  set(${complete} ${all_defined} PARENT_SCOPE)
endfunction()

# Appends to `errors_var` one line per include of `target` that names a folder it does not link.
function(_rigsim_check_target target errors_var)
  get_target_property(source_dir ${target} SOURCE_DIR)
  file(RELATIVE_PATH own_folder "${PROJECT_SOURCE_DIR}" "${source_dir}")
  _rigsim_link_closure(${target} closure complete)
  get_target_property(is_test ${target} RIGSIM_TEST)
  if("rigsim_testing" IN_LIST closure AND NOT is_test)
    set(errors "${${errors_var}}")
    list(APPEND errors "  ${target} links rigsim_testing, the test toolkit: only tests may (add_unit_test)")
    set(${errors_var} "${errors}" PARENT_SCOPE)
    return()
  endif()
  if(NOT complete)
    return()
  endif()
  get_target_property(sources ${target} SOURCES)
  set(queue "")
  foreach(source IN LISTS sources)
    if(source MATCHES "^\\$<")
      continue()
    endif()
    if(NOT IS_ABSOLUTE "${source}")
      set(source "${source_dir}/${source}")
    endif()
    if(source MATCHES "\\.(cc|h)$" AND EXISTS "${source}")
      list(APPEND queue "${source}")
    endif()
  endforeach()
  set(errors "${${errors_var}}")
  set(scanned "")
  while(queue)
    list(POP_FRONT queue file)
    if(file IN_LIST scanned)
      continue()
    endif()
    list(APPEND scanned "${file}")
    _rigsim_includes_of("${file}" includes)
    foreach(included IN LISTS includes)
      get_filename_component(folder "${included}" DIRECTORY)
      if(folder STREQUAL own_folder)
        list(APPEND queue "${PROJECT_SOURCE_DIR}/${included}")
        continue()
      endif()
      string(REPLACE "/" "_" library "rigsim_${folder}")
      if(NOT library IN_LIST closure)
        file(RELATIVE_PATH where "${PROJECT_SOURCE_DIR}" "${file}")
        list(APPEND errors "  ${where}: #include \"${included}\", but ${target} does not link ${library} (the library of ${folder}/)")
      endif()
    endforeach()
  endwhile()
  set(${errors_var} "${errors}" PARENT_SCOPE)
endfunction()

function(_rigsim_targets_in dir out)
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(subdir IN LISTS subdirs)
    _rigsim_targets_in("${subdir}" more)
    list(APPEND targets ${more})
  endforeach()
  set(${out} "${targets}" PARENT_SCOPE)
endfunction()

function(rigsim_check_layers)
  _rigsim_targets_in("${PROJECT_SOURCE_DIR}" targets)
  set(errors "")
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(type MATCHES "^(EXECUTABLE|STATIC_LIBRARY|SHARED_LIBRARY|OBJECT_LIBRARY|MODULE_LIBRARY)$")
      _rigsim_check_target(${target} errors)
    endif()
  endforeach()
  if(errors)
    list(JOIN errors "\n" lines)
    message(FATAL_ERROR "rigsim layering: a target includes a folder whose library it does not link "
                        "(link it, or include through a library that does), or links the test toolkit "
                        "without being a test (cmake/CheckLayers.cmake):\n${lines}")
  endif()
endfunction()
