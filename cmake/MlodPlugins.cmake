# add_exporter_plugin(<id>
#     NAME <text> VERSION <x.y.z> SUFFIXES <suffix> ... SOURCES <file> ...
#     [INTERFACE_VERSION <n>]   (default: the host's, 1; tests build older ones)
#     [OUTPUT_DIRECTORY <dir>]  (default: ${CMAKE_BINARY_DIR}/${MLOD_PLUGIN_RELDIR})
#     [NO_INSTALL] [STATIC])
#
# An exporter plugin (docs/architecture.md section 8): a MODULE library `mlod_plugin_<id>` that links
# mlod::sdk only, built into the build tree's plugin folder (which mirrors the install
# layout, so the host finds it from bin/ as it does from an installed prefix) and installed
# to ${MLOD_PLUGIN_RELDIR} (component "plugins").
#
# The plugin metadata that the host reads before loading is generated as
# ${CMAKE_CURRENT_BINARY_DIR}/<id>_metadata.json:
#     {"id", "name", "version", "suffixes": [...], "interfaceVersion"}
# and the plugin class names it:
#     Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "<id>_metadata.json")
# The same values reach the code as MLOD_PLUGIN_ID, MLOD_PLUGIN_NAME, MLOD_PLUGIN_VERSION
# (string literals) and MLOD_PLUGIN_SUFFIXES (a comma-separated string literal), so id(),
# name(), version() and suffixes() say what the metadata says.
#
# STATIC builds a static plugin instead (QT_STATICPLUGIN; a host links it and
# Q_IMPORT_PLUGIN(<ClassName>)s it).
function(add_exporter_plugin id)
  cmake_parse_arguments(ARG "NO_INSTALL;STATIC" "NAME;VERSION;INTERFACE_VERSION;OUTPUT_DIRECTORY" "SUFFIXES;SOURCES" ${ARGN})
  if(NOT ARG_NAME OR NOT ARG_VERSION OR NOT ARG_SUFFIXES OR NOT ARG_SOURCES)
    message(FATAL_ERROR "add_exporter_plugin(${id}): NAME, VERSION, SUFFIXES and SOURCES are required")
  endif()
  if(NOT id MATCHES "^[a-z0-9_-]+$")
    message(FATAL_ERROR "add_exporter_plugin(${id}): an id is [a-z0-9_-]+")
  endif()
  if(NOT DEFINED ARG_INTERFACE_VERSION)
    set(ARG_INTERFACE_VERSION 1)
  endif()
  if(NOT ARG_OUTPUT_DIRECTORY)
    set(ARG_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/${MLOD_PLUGIN_RELDIR}")
  endif()

  set(suffix_json "")
  foreach(suffix IN LISTS ARG_SUFFIXES)
    if(suffix_json)
      string(APPEND suffix_json ", ")
    endif()
    string(APPEND suffix_json "\"${suffix}\"")
  endforeach()
  string(REPLACE ";" "," suffix_list "${ARG_SUFFIXES}")
  file(CONFIGURE OUTPUT "${CMAKE_CURRENT_BINARY_DIR}/${id}_metadata.json" CONTENT
"{
  \"id\": \"${id}\",
  \"name\": \"${ARG_NAME}\",
  \"version\": \"${ARG_VERSION}\",
  \"suffixes\": [${suffix_json}],
  \"interfaceVersion\": ${ARG_INTERFACE_VERSION}
}
" @ONLY)

  set(target mlod_plugin_${id})
  if(ARG_STATIC)
    add_library(${target} STATIC ${ARG_SOURCES})
    target_compile_definitions(${target} PRIVATE QT_STATICPLUGIN)
  else()
    add_library(${target} MODULE ${ARG_SOURCES})
    set_target_properties(${target} PROPERTIES
      LIBRARY_OUTPUT_DIRECTORY "${ARG_OUTPUT_DIRECTORY}"
      OUTPUT_NAME "motionlod_${id}"
      CXX_VISIBILITY_PRESET hidden
      VISIBILITY_INLINES_HIDDEN ON)
    # core and runtime come in statically: keep their symbols inside the plugin
    target_link_options(${target} PRIVATE "LINKER:--exclude-libs,ALL")
  endif()
  set_target_properties(${target} PROPERTIES AUTOMOC ON POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PRIVATE "${CMAKE_CURRENT_BINARY_DIR}" "${CMAKE_CURRENT_SOURCE_DIR}")
  target_compile_definitions(${target} PRIVATE
    MLOD_PLUGIN_ID="${id}" MLOD_PLUGIN_NAME="${ARG_NAME}" MLOD_PLUGIN_VERSION="${ARG_VERSION}"
    MLOD_PLUGIN_SUFFIXES="${suffix_list}")
  target_link_libraries(${target} PRIVATE mlod::sdk)
  mlod_set_warnings(${target})
  if(NOT ARG_NO_INSTALL AND NOT ARG_STATIC)
    install(TARGETS ${target} LIBRARY DESTINATION ${MLOD_PLUGIN_RELDIR} COMPONENT plugins)
  endif()
endfunction()
