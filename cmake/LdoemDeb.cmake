# `cpack -G DEB` in the build folder: one package, ldoem_VERSION-1_amd64.deb, installed under /usr
# with its configuration in /etc. What lintian still says about it, and why, is in docs/service.md;
# scripts/check-deb-root.sh installs it into a clean Debian 12 root and scans through it.
set(LDOEM_MAINTAINER "ldoem authors <ldoem-maintainers@example.org>" CACHE STRING
    "The .deb's Maintainer field and its changelog's signature (Name <address>)")
set(LDOEM_DEB_VERSION ${PROJECT_VERSION}-1)  # -1: the first packaging of this upstream version

# changelog.Debian.gz, compressed as Debian wants it (gzip -9n: best, and no name or time stamp,
# so that two builds give the same bytes).
configure_file(${PROJECT_SOURCE_DIR}/packaging/debian/changelog.in ${PROJECT_BINARY_DIR}/debian/changelog.Debian @ONLY)
add_custom_command(OUTPUT ${PROJECT_BINARY_DIR}/debian/changelog.Debian.gz
  COMMAND gzip -9nkf ${PROJECT_BINARY_DIR}/debian/changelog.Debian
  DEPENDS ${PROJECT_BINARY_DIR}/debian/changelog.Debian VERBATIM)
add_custom_target(ldoem_deb_changelog ALL DEPENDS ${PROJECT_BINARY_DIR}/debian/changelog.Debian.gz)
ldoem_plain_ci_needs(ldoem_deb_changelog)
install(FILES ${PROJECT_BINARY_DIR}/debian/changelog.Debian.gz DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
# dpkg keeps an administrator's edits of a conffile across upgrades and asks before replacing it.
file(WRITE ${PROJECT_BINARY_DIR}/debian/conffiles "/etc/ldoem/hub.yaml\n")

set(CPACK_PACKAGE_NAME ldoem)
set(CPACK_PACKAGE_VENDOR "the ldoem authors")
set(CPACK_PACKAGE_CONTACT "${LDOEM_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "emulator and host driver for the SICK LD-OEM 3D laser scanner")
# The extended description: CPack indents each line and turns an empty one into " ."; Debian
# wants lines under 80 columns, so they are broken here.
string(JOIN "\n" CPACK_PACKAGE_DESCRIPTION
  "ldoem emulates a SICK LD-OEM laser range scanner, and the tilt stepper that"
  "turns it into a 3D scanner, at the level of the bytes on the wire, and"
  "drives real or emulated ones."
  ""
  "ldoem-emud answers the LD-OEM host protocol on CAN (ISO-TP), TCP and a"
  "serial line, and the stepper's pseudo-LPT register on a pty or a gpio chip,"
  "with profiles ray-cast (Embree) in a YAML scene whose objects may move (ODE)."
  "ldoem-scan takes a 3D scan to a PLY or PCD cloud and a preview; ldoem-hub"
  "serves many scanners to many clients; ldoem-conformance checks a device"
  "against the protocol; ldoem-replay serves a recorded conversation; ldoem-ctl"
  "injects faults into a running emulator."
  ""
  "Also included: hardened systemd units (ldoem-emud@.service,"
  "ldoem-emud-group@.service, ldoem-hub.service), example scenes, Wireshark"
  "dissectors, and libldoem, the host driver, as static libraries with"
  "headers, a CMake package and a pkg-config file.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # runtime library dependencies from dpkg-shlibdeps
set(CPACK_DEBIAN_PACKAGE_DEPENDS "systemd")
if(TARGET ldoem_python_extension)
  # The extension is built for this interpreter's ABI (python/CMakeLists.txt).
  set(CPACK_DEBIAN_PACKAGE_DEPENDS
      "systemd, python3 (>= ${LDOEM_PYTHON_ABI}), python3 (<< ${LDOEM_PYTHON_ABI_NEXT}), python3-numpy")
endif()
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "tshark | wireshark")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${PROJECT_BINARY_DIR}/debian/conffiles)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
