# cmake --install and CPack (docs/service.md): the programs with their man pages and bash
# completions, the scenes, the docs, the systemd units, the hub's configuration, the Wireshark
# dissectors, and libldoem for other people's programs: static libldoem.a + libldoem_protocol.a,
# libldoem_base.a, their headers, a CMake package (find_package(ldoem) -> ldoem::driver) and
# ldoem.pc. Only what this configuration builds is installed (LDOEM_ONLY may leave parts out).
include(CMakePackageConfigHelpers)

set(ldoem_programs ldoem-emud ldoem-hub ldoem-scan ldoem-conformance ldoem-ctl ldoem-replay)
# One line each for the man page's NAME section (help2man --name).
set(ldoem-emud_summary "emulate a SICK LD-OEM laser scanner at the byte level")
set(ldoem-hub_summary "serve LD-OEM scanners to many clients (generic interface)")
set(ldoem-scan_summary "take a 3D scan with an LD-OEM and its tilt stepper")
set(ldoem-conformance_summary "check a device against the LD-OEM host protocol")
set(ldoem-ctl_summary "talk to ldoem-emud's control socket")
set(ldoem-replay_summary "serve a recorded LD-OEM conversation as a device (ldoem-emud --replay)")

find_program(LDOEM_HELP2MAN help2man)
if(NOT LDOEM_HELP2MAN)
  message(STATUS "help2man not found: no man pages (scripts/install-deps.sh installs it)")
endif()
# Not in a sanitizer build's `all`: nothing installs from it, and a sanitized --help is slower.
if(LDOEM_SANITIZE OR LDOEM_TSAN OR LDOEM_FUZZ)
  add_custom_target(ldoem_man_and_completions)
else()
  add_custom_target(ldoem_man_and_completions ALL)
endif()
ldoem_plain_ci_needs(ldoem_man_and_completions)  # scripts/check-install.sh installs them
foreach(program ${ldoem_programs})
  if(NOT TARGET ${program})
    continue()
  endif()
  install(TARGETS ${program} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  set(generated)
  # Man pages from each program's --help-all (the full text; --help is one screen of it), at
  # build time, so they never drift from it; the version is the project's, which each
  # program's --version prints too.
  if(LDOEM_HELP2MAN)
    # gzip -9n, as Debian keeps man pages (and without a time stamp: the same bytes each build).
    set(page ${PROJECT_BINARY_DIR}/man/${program}.1.gz)
    add_custom_command(OUTPUT ${page}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/man
      COMMAND ${LDOEM_HELP2MAN} --no-info --no-discard-stderr --help-option=--help-all --section 1 --source ldoem
              --version-string "${PROJECT_VERSION}" --name "${${program}_summary}"
              --output ${PROJECT_BINARY_DIR}/man/${program}.1 $<TARGET_FILE:${program}>
      COMMAND gzip -9nf ${PROJECT_BINARY_DIR}/man/${program}.1
      DEPENDS ${program} VERBATIM COMMENT "Man page ${program}.1")
    install(FILES ${page} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)
    list(APPEND generated ${page})
  endif()
  # A bash completion from `--completion bash` (base/command_line.hpp).
  set(completion ${PROJECT_BINARY_DIR}/completions/${program})
  add_custom_command(OUTPUT ${completion}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/completions
    COMMAND sh -c "\"$1\" --completion bash >\"$2\"" sh $<TARGET_FILE:${program}> ${completion}
    DEPENDS ${program} VERBATIM COMMENT "Bash completion ${program}")
  install(FILES ${completion} DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions COMPONENT runtime)
  list(APPEND generated ${completion})
  if(generated)
    add_custom_target(${program}_man_and_completion DEPENDS ${generated})
    add_dependencies(ldoem_man_and_completions ${program}_man_and_completion)
  endif()
endforeach()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ldoem/scenes COMPONENT runtime)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/packaging/systemd/ldoem-emud.env.example
              ${PROJECT_SOURCE_DIR}/packaging/debian/copyright
        DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
# systemd looks in <prefix>/lib/systemd/system for /usr (Debian's merged /usr) and /usr/local.
install(FILES ${PROJECT_SOURCE_DIR}/packaging/systemd/ldoem-emud@.service
              ${PROJECT_SOURCE_DIR}/packaging/systemd/ldoem-emud-group@.service
              ${PROJECT_SOURCE_DIR}/packaging/systemd/ldoem-hub.service
        DESTINATION lib/systemd/system COMPONENT runtime)
# Wireshark loads Lua dissectors from its global plugin folder (`tshark -G folders`: "Global
# Lua Plugins", /usr/lib/x86_64-linux-gnu/wireshark/plugins on Debian 12), not from a
# versioned subfolder, and in name order: ldoem.lua before ldoem_serial.lua, which needs it.
install(FILES ${PROJECT_SOURCE_DIR}/tools/wireshark/ldoem.lua ${PROJECT_SOURCE_DIR}/tools/wireshark/ldoem_serial.lua
        DESTINATION lib/${CMAKE_LIBRARY_ARCHITECTURE}/wireshark/plugins COMPONENT runtime)
# The hub's configuration goes where ldoem-hub.service reads it: /etc/ldoem for the prefix /usr
# (the .deb, `cmake --install --prefix /usr`), PREFIX/etc/ldoem for any other prefix. Decided at
# install time, because `--prefix` and CPack's prefix are not known when CMake configures.
install(CODE "
  if(CMAKE_INSTALL_PREFIX STREQUAL \"/usr\")
    set(ldoem_etc /etc/ldoem)
  else()
    set(ldoem_etc \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_SYSCONFDIR}/ldoem\")
  endif()
  file(INSTALL \"${PROJECT_SOURCE_DIR}/packaging/etc/hub.yaml\" DESTINATION \"\${ldoem_etc}\")
" COMPONENT runtime)

if(TARGET ldoem_driver AND TARGET ldoem_protocol)
  set_target_properties(ldoem_driver PROPERTIES EXPORT_NAME driver OUTPUT_NAME ldoem)
  set_target_properties(ldoem_protocol PROPERTIES EXPORT_NAME protocol)
  set_target_properties(ldoem_base PROPERTIES EXPORT_NAME base)
  install(TARGETS ldoem_driver ldoem_protocol ldoem_base EXPORT ldoemTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
          INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/base/include/ldoem ${PROJECT_SOURCE_DIR}/protocol/include/ldoem
                    ${PROJECT_SOURCE_DIR}/driver/lib/include/ldoem
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development)
  set(package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/ldoem)
  install(EXPORT ldoemTargets NAMESPACE ldoem:: DESTINATION ${package_dir} COMPONENT development)
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ldoemConfig.cmake.in
                                ${PROJECT_BINARY_DIR}/ldoemConfig.cmake INSTALL_DESTINATION ${package_dir})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/ldoemConfigVersion.cmake
                                   COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/ldoemConfig.cmake ${PROJECT_BINARY_DIR}/ldoemConfigVersion.cmake
          DESTINATION ${package_dir} COMPONENT development)
  # ldoem.pc finds the prefix from where it lies (pkg-config's ${pcfiledir}), so one file serves
  # the .deb (/usr), /usr/local and any `cmake --install --prefix DIR`.
  file(RELATIVE_PATH LDOEM_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
  string(REGEX REPLACE "/$" "" LDOEM_PC_TO_PREFIX "${LDOEM_PC_TO_PREFIX}")  # ../.. for lib/pkgconfig
  configure_file(${PROJECT_SOURCE_DIR}/cmake/ldoem.pc.in ${PROJECT_BINARY_DIR}/ldoem.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/ldoem.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT development)
endif()

include(cmake/LdoemDeb.cmake)
