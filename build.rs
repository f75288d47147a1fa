//! Builds surfkit's C++ side: the OpenMesh bridge (cxx) and the OpenSubdiv C shim
//! (bindgen + cc), against the system libraries from Debian's packages.
//!
//! A missing library stops the build with a message naming the package to install.
//! `OPENMESH_DIR` / `OPENSUBDIV_DIR` name another install prefix (with `include/` and `lib/`).

use std::env;
use std::path::PathBuf;

/// A system C++ library surfkit links against.
struct SystemLibrary {
    name: &'static str,
    debian_package: &'static str,
    prefix_variable: &'static str,
    /// A header that must exist, relative to the include folder.
    header: &'static str,
    /// Libraries to link (without `lib` and `.so`).
    link: &'static [&'static str],
}

const OPENMESH: SystemLibrary = SystemLibrary {
    name: "OpenMesh",
    debian_package: "libopenmesh-dev",
    prefix_variable: "OPENMESH_DIR",
    header: "OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh",
    link: &["OpenMeshCore"],
};

const OPENSUBDIV: SystemLibrary = SystemLibrary {
    name: "OpenSubdiv",
    debian_package: "libosd-dev",
    prefix_variable: "OPENSUBDIV_DIR",
    header: "opensubdiv/far/topologyRefinerFactory.h",
    link: &["osdCPU"],
};

/// Where a library was found: its include folder and library folder.
struct Found {
    include: PathBuf,
    lib: Option<PathBuf>,
}

fn find(lib: &SystemLibrary) -> Found {
    println!("cargo:rerun-if-env-changed={}", lib.prefix_variable);
    let mut prefixes: Vec<PathBuf> = Vec::new();
    if let Ok(p) = env::var(lib.prefix_variable) {
        prefixes.push(PathBuf::from(p));
    }
    prefixes.push(PathBuf::from("/usr"));
    prefixes.push(PathBuf::from("/usr/local"));
    let multiarch = format!(
        "lib/{}-linux-gnu",
        env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default()
    );
    for prefix in &prefixes {
        let include = prefix.join("include");
        if !include.join(lib.header).exists() {
            continue;
        }
        let lib_dir = [multiarch.as_str(), "lib", "lib64"]
            .iter()
            .map(|d| prefix.join(d))
            .find(|d| {
                lib.link.iter().all(|l| {
                    d.join(format!("lib{l}.so")).exists() || d.join(format!("lib{l}.a")).exists()
                })
            });
        if lib_dir.is_none() {
            fail(
                lib,
                &format!(
                    "found its headers in {} but not the libraries {:?}",
                    include.display(),
                    lib.link
                ),
            );
        }
        return Found {
            include,
            lib: lib_dir,
        };
    }
    fail(
        lib,
        &format!("header {} not found under {:?}", lib.header, prefixes),
    )
}

fn fail(lib: &SystemLibrary, detail: &str) -> ! {
    panic!(
        "\n\nsurfkit needs {name}: {detail}.\nInstall it with:  apt-get install {pkg}\n(or set {var} to an install prefix that has include/ and lib/)\n\n",
        name = lib.name,
        pkg = lib.debian_package,
        var = lib.prefix_variable
    );
}

fn link(lib: &SystemLibrary, found: &Found) {
    if let Some(dir) = &found.lib {
        println!("cargo:rustc-link-search=native={}", dir.display());
    }
    for l in lib.link {
        println!("cargo:rustc-link-lib=dylib={l}");
    }
}

fn main() {
    let openmesh = find(&OPENMESH);
    let opensubdiv = find(&OPENSUBDIV);

    // OpenMesh bridge (cxx).
    let mut om = cxx_build::bridge("src/ffi/openmesh.rs");
    om.file("cpp/openmesh/bridge.cpp")
        .include(&openmesh.include)
        .std("c++17")
        .define("_USE_MATH_DEFINES", None)
        .flag_if_supported("-Wno-deprecated-copy")
        .flag_if_supported("-Wno-unused-parameter")
        .flag_if_supported("-Wno-maybe-uninitialized");
    // OpenMesh's inline code asserts handles on every access unless NDEBUG (as its own
    // Debian build does): off in release builds, on in debug builds.
    if env::var("PROFILE").as_deref() == Ok("release") {
        om.define("NDEBUG", None);
    }
    om.compile("surfkit_openmesh");
    link(&OPENMESH, &openmesh);

    // OpenSubdiv shim (plain C header for bindgen, C++ body compiled with cc).
    cc::Build::new()
        .cpp(true)
        .file("cpp/opensubdiv/shim.cpp")
        .include(&opensubdiv.include)
        .std("c++17")
        .compile("surfkit_opensubdiv");
    link(&OPENSUBDIV, &opensubdiv);

    let out = PathBuf::from(env::var("OUT_DIR").unwrap());
    bindgen::Builder::default()
        .header("cpp/opensubdiv/shim.h")
        .allowlist_function("surfkit_osd_.*")
        .allowlist_type("surfkit_osd_.*")
        .allowlist_var("SURFKIT_OSD_.*")
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()))
        .generate()
        .unwrap_or_else(|e| panic!("bindgen failed on cpp/opensubdiv/shim.h: {e}\n(bindgen needs libclang: apt-get install libclang-dev)"))
        .write_to_file(out.join("opensubdiv_shim.rs"))
        .expect("writing the OpenSubdiv bindings");

    for dir in ["cpp/openmesh", "cpp/opensubdiv"] {
        for entry in std::fs::read_dir(dir).unwrap().flatten() {
            println!("cargo:rerun-if-changed={}", entry.path().display());
        }
    }
    println!("cargo:rerun-if-changed=src/ffi/openmesh.rs");
}
