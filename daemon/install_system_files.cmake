# Installs tumbled's configuration and the systemd units (tumbled, tumble-view) for the prefix given at
# install time (`cmake --install build --prefix /usr`), with GNUInstallDirs'
# sysconfdir rule: /etc for the prefixes / and /usr, /etc/opt/X for /opt/X,
# <prefix>/etc otherwise. The unit's ExecStart and --config follow.
# Set by the caller: TUMBLE_SOURCE_DIR, TUMBLE_BINARY_DIR, TUMBLE_BINDIR.
set(_prefix "${CMAKE_INSTALL_PREFIX}")
if(_prefix STREQUAL "/usr" OR _prefix STREQUAL "/")
  set(_etc "/etc")
elseif(_prefix MATCHES "^/opt/")
  set(_etc "/etc${_prefix}")
else()
  set(_etc "${_prefix}/etc")
endif()
file(INSTALL "${TUMBLE_SOURCE_DIR}/config/tumbled.yaml" DESTINATION "${_etc}/tumble")

file(READ "${TUMBLE_SOURCE_DIR}/systemd/tumbled.service" _unit)
string(REPLACE "/usr/bin/tumbled" "${_prefix}/${TUMBLE_BINDIR}/tumbled" _unit "${_unit}")
string(REPLACE "/etc/tumble/" "${_etc}/tumble/" _unit "${_unit}")
file(WRITE "${TUMBLE_BINARY_DIR}/tumbled.service" "${_unit}")
file(INSTALL "${TUMBLE_BINARY_DIR}/tumbled.service" DESTINATION "${_prefix}/lib/systemd/system")

file(READ "${TUMBLE_SOURCE_DIR}/systemd/tumble-view.service" _view_unit)
string(REPLACE "/usr/bin/tumble-view" "${_prefix}/${TUMBLE_BINDIR}/tumble-view" _view_unit "${_view_unit}")
file(WRITE "${TUMBLE_BINARY_DIR}/tumble-view.service" "${_view_unit}")
file(INSTALL "${TUMBLE_BINARY_DIR}/tumble-view.service" DESTINATION "${_prefix}/lib/systemd/system")
