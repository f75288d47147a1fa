//! Gives the shared library its soname, so programs linked against libsurfkit.so load
//! libsurfkit.so.0 and a later ABI-compatible build can replace it; and exports the OpenMesh
//! functions the shim instantiates (see cpp/openmesh/export.map: a hidden copy makes every
//! devirtualized call inside libOpenMeshCore miss its guard).
fn main() {
    println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libsurfkit.so.0");
    let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../cpp/openmesh/export.map");
    println!(
        "cargo:rustc-cdylib-link-arg=-Wl,--version-script={}",
        map.display()
    );
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed={}", map.display());
}
