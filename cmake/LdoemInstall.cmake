# cmake --install and CPack (docs/service.md): the programs, the scenes, the docs, the systemd
# units, and libldoem for other people's programs: static libldoem.a + libldoem_protocol.a,
# libldoem_base.a, their headers, a CMake package (find_package(ldoem) -> ldoem::driver) and ldoem.pc.
# Only what this configuration builds is installed (LDOEM_ONLY may leave parts out).
include(CMakePackageConfigHelpers)

foreach(program ldoem-emud ldoem-hub ldoem-scan ldoem-conformance)
  if(TARGET ${program})
    install(TARGETS ${program} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  endif()
endforeach()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ldoem/scenes COMPONENT runtime)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/packaging/systemd/ldoem-emud.env.example
        DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
# systemd looks in <prefix>/lib/systemd/system for /usr (Debian's merged /usr) and /usr/local.
install(FILES ${PROJECT_SOURCE_DIR}/packaging/systemd/ldoem-emud@.service
              ${PROJECT_SOURCE_DIR}/packaging/systemd/ldoem-emud-group@.service
              ${PROJECT_SOURCE_DIR}/packaging/systemd/ldoem-hub.service
        DESTINATION lib/systemd/system COMPONENT runtime)
install(FILES ${PROJECT_SOURCE_DIR}/packaging/etc/hub.yaml DESTINATION ${CMAKE_INSTALL_SYSCONFDIR}/ldoem COMPONENT runtime)

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
  configure_file(${PROJECT_SOURCE_DIR}/cmake/ldoem.pc.in ${PROJECT_BINARY_DIR}/ldoem.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/ldoem.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT development)
endif()

# cpack -G DEB in the build folder: one package, installed under /usr.
set(CPACK_PACKAGE_NAME ldoem)
set(CPACK_PACKAGE_VENDOR "ldoem")
set(CPACK_PACKAGE_CONTACT "ldoem maintainers <ldoem@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # runtime library dependencies from dpkg-shlibdeps
set(CPACK_DEBIAN_PACKAGE_DEPENDS "systemd")
if(TARGET ldoem_python_extension)
  # The extension is built for this interpreter's ABI (python/CMakeLists.txt).
  set(CPACK_DEBIAN_PACKAGE_DEPENDS
      "systemd, python3 (>= ${LDOEM_PYTHON_ABI}), python3 (<< ${LDOEM_PYTHON_ABI_NEXT}), python3-numpy")
endif()
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
