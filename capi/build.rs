//! Gives the shared library its soname, so programs linked against libsurfkit.so load
//! libsurfkit.so.0 and a later ABI-compatible build can replace it.
fn main() {
    println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libsurfkit.so.0");
    println!("cargo:rerun-if-changed=build.rs");
}
