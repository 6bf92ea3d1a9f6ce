# Install rules shared by every component, and CPack (DEB + TGZ). Included at the end of the
# top-level CMakeLists, after every target exists.
#
# Components (cmake --install BUILD --component NAME):
#   app      motionlod-studio and its man page, desktop entry, icons, AppStream metadata, the sample
#   cli      motionlod, its man page and the farm specs (Kubernetes, HTCondor)
#   plugins  the exporter plugins (add_exporter_plugin() installs them)
#   sdk      mlod_runtime (static) + headers under include/motionlod/runtime and a CMake
#            package: find_package(MotionLODRuntime) gives mlod::runtime
# Every component carries the licence files, so each can be redistributed alone.
# The exporter SDK (src/sdk) is not packaged: its headers include core's and Qt's and a
# plugin links core statically, so plugins are built in this tree (docs/plugin-guide.md).
#
# CPack builds ONE package holding all four components (motionlod_<v>_<arch>.deb and
# motionlod-<v>-Linux-<arch>.tar.gz): the studio, the CLI and the plugins are built from the
# same static core and must match exactly, the whole is a few MB, and a technical artist
# wants both tools and every exporter from one install. Split packages would need a shared
# "-common" package for the licences and sample; not worth it at this size.
#
# Relocation: nothing in-tree is a shared library, so the executables need no RUNPATH to
# find our code (the top-level sets $ORIGIN/../<libdir> for builds with BUILD_SHARED_LIBS);
# plugins are found relative to the executable (src/sdk/plugin_paths.*) and the sample too
# (src/app/main.cpp), so the unpacked TGZ runs from any folder.

include(CMakePackageConfigHelpers)

set(MLOD_PACKAGE_NAME "motionlod")
set(MLOD_DOCDIR "${CMAKE_INSTALL_DATADIR}/doc/${MLOD_PACKAGE_NAME}")
set(MLOD_PACKAGE_MAINTAINER "Motion LOD Studio maintainers <motionlod@localhost>" CACHE STRING
    "Maintainer written into the DEB (Name <email>)")
set(MLOD_PACKAGE_HOMEPAGE "" CACHE STRING "Project home page written into the DEB and AppStream metadata (none if empty)")

# --- licence files, in every component -------------------------------------------------
# share/doc/motionlod/copyright (Debian's machine-readable format) and changelog.gz are
# where Debian tools and people look; LICENSE and the notices are the sources' own.
set(MLOD_CHANGELOG_GZ ${CMAKE_BINARY_DIR}/installer/changelog.gz)
add_custom_command(OUTPUT ${MLOD_CHANGELOG_GZ}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/installer
  COMMAND gzip -9 -n -c ${PROJECT_SOURCE_DIR}/CHANGELOG.md > ${MLOD_CHANGELOG_GZ}
  DEPENDS ${PROJECT_SOURCE_DIR}/CHANGELOG.md
  COMMENT "Compressing the changelog")
add_custom_target(mlod_changelog ALL DEPENDS ${MLOD_CHANGELOG_GZ})
foreach(component app cli plugins sdk)
  install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/THIRD-PARTY-NOTICES.md
                ${PROJECT_SOURCE_DIR}/installer/copyright ${MLOD_CHANGELOG_GZ}
          DESTINATION ${MLOD_DOCDIR} COMPONENT ${component})
endforeach()

if(MLOD_BUILD_QT)
  # --- app: icons (hicolor PNGs rendered from the one SVG at build time) -----------------
  find_package(Qt6 6.4 REQUIRED COMPONENTS Svg)
  qt_add_executable(mlod_render_icon ${PROJECT_SOURCE_DIR}/installer/icons/render_icon.cpp)
  set_target_properties(mlod_render_icon PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tools)
  target_link_libraries(mlod_render_icon PRIVATE Qt6::Gui Qt6::Svg)
  mlod_set_warnings(mlod_render_icon)

  set(MLOD_ICON_SVG ${PROJECT_SOURCE_DIR}/installer/icons/motionlod-studio.svg)
  set(MLOD_ICON_SIZES 16 22 24 32 48 64 128 256)
  set(MLOD_ICON_DIR ${CMAKE_BINARY_DIR}/icons/hicolor)
  set(MLOD_ICON_PNGS "")
  foreach(size ${MLOD_ICON_SIZES})
    list(APPEND MLOD_ICON_PNGS ${MLOD_ICON_DIR}/${size}x${size}/apps/motionlod-studio.png)
  endforeach()
  add_custom_command(OUTPUT ${MLOD_ICON_PNGS}
    COMMAND mlod_render_icon ${MLOD_ICON_SVG} ${MLOD_ICON_DIR} motionlod-studio ${MLOD_ICON_SIZES}
    DEPENDS mlod_render_icon ${MLOD_ICON_SVG}
    COMMENT "Rendering the studio icon to ${MLOD_ICON_SIZES} px" VERBATIM)
  add_custom_target(mlod_icons ALL DEPENDS ${MLOD_ICON_PNGS})
  foreach(size ${MLOD_ICON_SIZES})
    install(FILES ${MLOD_ICON_DIR}/${size}x${size}/apps/motionlod-studio.png
            DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/${size}x${size}/apps COMPONENT app)
  endforeach()
  install(FILES ${MLOD_ICON_SVG} DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/scalable/apps COMPONENT app)

  # --- app: AppStream metadata (the desktop entry and sample are installed by src/app) ----
  configure_file(${PROJECT_SOURCE_DIR}/installer/org.motionlod.Studio.metainfo.xml.in
                 ${CMAKE_BINARY_DIR}/installer/org.motionlod.Studio.metainfo.xml @ONLY)
  install(FILES ${CMAKE_BINARY_DIR}/installer/org.motionlod.Studio.metainfo.xml
          DESTINATION ${CMAKE_INSTALL_DATADIR}/metainfo COMPONENT app)

  # --- man pages (cli: motionlod, app: motionlod-studio), gzipped as Debian installs them --
  foreach(page_component motionlod:cli motionlod-studio:app)
    string(REPLACE ":" ";" page_component ${page_component})
    list(GET page_component 0 page)
    list(GET page_component 1 component)
    add_custom_command(OUTPUT ${CMAKE_BINARY_DIR}/installer/${page}.1.gz
      COMMAND gzip -9 -n -c ${PROJECT_SOURCE_DIR}/installer/${page}.1 > ${CMAKE_BINARY_DIR}/installer/${page}.1.gz
      DEPENDS ${PROJECT_SOURCE_DIR}/installer/${page}.1
      COMMENT "Compressing the ${page} man page")
    add_custom_target(mlod_man_${component} ALL DEPENDS ${CMAKE_BINARY_DIR}/installer/${page}.1.gz)
    install(FILES ${CMAKE_BINARY_DIR}/installer/${page}.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT ${component})
  endforeach()
  # --- cli: the farm specs (docs/farm.md), ready to copy and edit ------------------------
  install(FILES ${PROJECT_SOURCE_DIR}/installer/farm/kubernetes-indexed-job.yaml
                ${PROJECT_SOURCE_DIR}/installer/farm/motionlod.sub
          DESTINATION ${CMAKE_INSTALL_DATADIR}/motionlod/farm COMPONENT cli)
endif()

# --- plugins: no RUNPATH ----------------------------------------------------------------
# The executables' $ORIGIN/../<libdir> means nothing from <libdir>/motionlod/plugins, and a
# plugin needs no in-tree shared library (core and the SDK come in statically).
if(MLOD_BUILD_QT AND EXISTS ${PROJECT_SOURCE_DIR}/plugins/CMakeLists.txt)
  get_property(mlod_plugin_dirs DIRECTORY ${PROJECT_SOURCE_DIR}/plugins PROPERTY SUBDIRECTORIES)
  foreach(dir ${mlod_plugin_dirs})
    get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
    foreach(target ${targets})
      get_target_property(type ${target} TYPE)
      if(type STREQUAL "MODULE_LIBRARY")
        set_target_properties(${target} PROPERTIES INSTALL_RPATH "")
      endif()
    endforeach()
  endforeach()
endif()

# --- sdk: find_package(MotionLODRuntime) -----------------------------------------------
# src/runtime/CMakeLists.txt installs the library and its headers into the export set.
set(MLOD_RUNTIME_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/MotionLODRuntime)
install(EXPORT MotionLODRuntimeTargets NAMESPACE mlod:: FILE MotionLODRuntimeTargets.cmake
        DESTINATION ${MLOD_RUNTIME_CMAKEDIR} COMPONENT sdk)
configure_package_config_file(${PROJECT_SOURCE_DIR}/installer/MotionLODRuntimeConfig.cmake.in
  ${CMAKE_BINARY_DIR}/installer/MotionLODRuntimeConfig.cmake INSTALL_DESTINATION ${MLOD_RUNTIME_CMAKEDIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/installer/MotionLODRuntimeConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/installer/MotionLODRuntimeConfig.cmake
              ${CMAKE_BINARY_DIR}/installer/MotionLODRuntimeConfigVersion.cmake
        DESTINATION ${MLOD_RUNTIME_CMAKEDIR} COMPONENT sdk)

# --- CPack -----------------------------------------------------------------------------
set(CPACK_PACKAGE_NAME ${MLOD_PACKAGE_NAME})
set(CPACK_PACKAGE_VENDOR "Motion LOD Studio")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Motion level-of-detail authoring for crowds: studio, CLI, exporters")
# Lines under 80 columns with the leading space the .deb control file adds.
set(CPACK_PACKAGE_DESCRIPTION
"Motion LOD Studio simplifies character motion and meshes for crowds. Joint
posture clustering (Ahn and Wohn, Motion Level-of-Detail) freezes each joint
over runs of frames that stay within an error bound, and the skinned mesh is
simplified per joint segment. The package holds the Qt studio
(motionlod-studio), the batch command line (motionlod), the exporter plugins
(glTF 2.0, runtime bundle, report), the runtime library and headers for
engines (find_package(MotionLODRuntime)), and a sample clip.")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGE_CONTACT "${MLOD_PACKAGE_MAINTAINER}")
set(CPACK_STRIP_FILES ON)
set(CPACK_SOURCE_IGNORE_FILES "/build.*/;/\\\\.git/")
set(CPACK_GENERATOR "DEB;TGZ")
set(CPACK_COMPONENTS_ALL app cli plugins sdk)
set(CPACK_COMPONENT_APP_DISPLAY_NAME "Motion LOD Studio")
set(CPACK_COMPONENT_CLI_DISPLAY_NAME "motionlod command line")
set(CPACK_COMPONENT_PLUGINS_DISPLAY_NAME "Exporter plugins")
set(CPACK_COMPONENT_SDK_DISPLAY_NAME "Runtime SDK (static library, headers, CMake package)")

# TGZ: motionlod-<version>-Linux-<arch>/{bin,lib,share,include}, runnable where unpacked.
set(CPACK_ARCHIVE_COMPONENT_INSTALL OFF)
set(CPACK_PACKAGE_FILE_NAME "${MLOD_PACKAGE_NAME}-${PROJECT_VERSION}-Linux-${CMAKE_SYSTEM_PROCESSOR}")

# DEB: installs under /usr (CPACK_PACKAGING_INSTALL_PREFIX); configure with
# -DCMAKE_INSTALL_PREFIX=/usr so GNUInstallDirs picks the multiarch libdir Debian uses.
if(NOT CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  message(STATUS "Packaging: CMAKE_INSTALL_PREFIX is ${CMAKE_INSTALL_PREFIX}, so the .deb puts libraries and "
                 "plugins in /usr/${CMAKE_INSTALL_LIBDIR} (it works, but release packages want Debian's multiarch "
                 "folder: configure with -DCMAKE_INSTALL_PREFIX=/usr)")
endif()
set(CPACK_DEB_COMPONENT_INSTALL OFF)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${MLOD_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION "graphics")
set(CPACK_DEBIAN_PACKAGE_PRIORITY "optional")
if(MLOD_PACKAGE_HOMEPAGE)
  set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "${MLOD_PACKAGE_HOMEPAGE}")
endif()
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Software OpenGL where the machine has no GPU driver; the SDK's CMake package needs GLM.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libgl1-mesa-dri")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libglm-dev, cmake")

include(CPack)

# The package tests (label "package") run cpack on this tree; they live beside the other
# tests but are added here, where the packaging they check is defined.
if(MLOD_BUILD_TESTS AND MLOD_BUILD_QT)
  add_subdirectory(${PROJECT_SOURCE_DIR}/tests/package ${CMAKE_BINARY_DIR}/tests/package)
endif()
