#!/usr/bin/env bash
# Installs surfkit for C and C++ programs:  bash scripts/install-cpp.sh [PREFIX]   (default /usr/local)
#   PREFIX/lib/libsurfkit.so.0 (+ libsurfkit.so), PREFIX/lib/libsurfkit.a,
#   PREFIX/include/surfkit.h, PREFIX/include/surfkit/openmesh.hh,
#   PREFIX/lib/pkgconfig/surfkit.pc            (pkg-config --cflags --libs surfkit)
#   PREFIX/lib/cmake/surfkit/surfkitConfig.cmake (find_package(surfkit CONFIG REQUIRED),
#                                                 target surfkit::surfkit)
# Builds the C ABI (cargo build --release -p surfkit-capi) unless SURFKIT_BUILT_LIBS names a
# folder that already holds libsurfkit.so and libsurfkit.a (the tests use that).
set -euo pipefail
prefix=${1:-/usr/local}
root=$(cd "$(dirname "$0")/.." && pwd)
version=$(sed -n 's/^version = "\(.*\)"/\1/p' "$root/capi/Cargo.toml" | head -n 1)
built=${SURFKIT_BUILT_LIBS:-}
if [ -z "$built" ]; then
  (cd "$root" && cargo build --release -p surfkit-capi)
  built="$root/target/release"
fi
for f in libsurfkit.so libsurfkit.a; do
  [ -f "$built/$f" ] || { echo "install-cpp: $built/$f is missing (build with cargo build --release -p surfkit-capi)" >&2; exit 1; }
done
mkdir -p "$prefix"
prefix=$(cd "$prefix" && pwd)
lib="$prefix/lib"
install -d "$lib/pkgconfig" "$lib/cmake/surfkit" "$prefix/include/surfkit"
install -m 644 "$built/libsurfkit.a" "$lib/libsurfkit.a"
install -m 755 "$built/libsurfkit.so" "$lib/libsurfkit.so.$version"
ln -sf "libsurfkit.so.$version" "$lib/libsurfkit.so.0"
ln -sf libsurfkit.so.0 "$lib/libsurfkit.so"
install -m 644 "$root/include/surfkit.h" "$prefix/include/surfkit.h"
install -m 644 "$root/include/surfkit/openmesh.hh" "$prefix/include/surfkit/openmesh.hh"

# What a static link of libsurfkit.a needs besides OpenMesh: OpenSubdiv, the C++ runtime
# and what Rust's standard library links.
private="-losdCPU -lOpenMeshCore -lstdc++ -lgcc_s -lutil -lrt -lpthread -lm -ldl -lc"
cat > "$lib/pkgconfig/surfkit.pc" <<PC
prefix=$prefix
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: surfkit
Description: Quality of surface models: Euler Accompanying Test, spline hole filling, Catmull-Clark fairing
Version: $version
Requires: openmesh
Libs: -L\${libdir} -lsurfkit
Libs.private: $private
Cflags: -I\${includedir}
PC

cat > "$lib/cmake/surfkit/surfkitConfig.cmake" <<'CMAKE'
# surfkit's CMake package: find_package(surfkit CONFIG REQUIRED) gives the imported targets
# surfkit::surfkit (shared) and surfkit::surfkit_static, each with the include folder and
# OpenMesh (Debian's OpenMeshConfig.cmake) as a usage requirement.
include(CMakeFindDependencyMacro)
find_dependency(OpenMesh CONFIG)
find_dependency(Threads)
get_filename_component(_surfkit_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET surfkit::surfkit)
  add_library(surfkit::surfkit SHARED IMPORTED)
  set_target_properties(surfkit::surfkit PROPERTIES
    IMPORTED_LOCATION "${_surfkit_prefix}/lib/libsurfkit.so.0"
    IMPORTED_SONAME "libsurfkit.so.0"
    INTERFACE_INCLUDE_DIRECTORIES "${_surfkit_prefix}/include"
    INTERFACE_LINK_LIBRARIES "OpenMeshCore"
    INTERFACE_COMPILE_FEATURES "cxx_std_17")
  add_library(surfkit::surfkit_static STATIC IMPORTED)
  set_target_properties(surfkit::surfkit_static PROPERTIES
    IMPORTED_LOCATION "${_surfkit_prefix}/lib/libsurfkit.a"
    INTERFACE_INCLUDE_DIRECTORIES "${_surfkit_prefix}/include"
    INTERFACE_LINK_LIBRARIES "OpenMeshCore;osdCPU;stdc++;Threads::Threads;m;dl;rt;util"
    INTERFACE_COMPILE_FEATURES "cxx_std_17")
endif()
unset(_surfkit_prefix)
CMAKE
sed "s/@VERSION@/$version/" > "$lib/cmake/surfkit/surfkitConfigVersion.cmake" <<'CMAKE'
set(PACKAGE_VERSION "@VERSION@")
if(PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION)
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
else()
  string(REGEX MATCH "^[0-9]+\\.[0-9]+" _have "${PACKAGE_VERSION}")
  string(REGEX MATCH "^[0-9]+\\.[0-9]+" _want "${PACKAGE_FIND_VERSION}")
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
  if(PACKAGE_FIND_VERSION AND NOT _have STREQUAL _want)
    set(PACKAGE_VERSION_COMPATIBLE FALSE)
  endif()
  if(PACKAGE_FIND_VERSION STREQUAL PACKAGE_VERSION)
    set(PACKAGE_VERSION_EXACT TRUE)
  endif()
endif()
CMAKE
if [ "$(id -u)" = 0 ] && command -v ldconfig >/dev/null && { [ "$prefix" = /usr/local ] || [ "$prefix" = /usr ]; }; then
  ldconfig
fi
echo "surfkit $version installed in $prefix (pkg-config: PKG_CONFIG_PATH=$lib/pkgconfig; CMake: CMAKE_PREFIX_PATH=$prefix)"
