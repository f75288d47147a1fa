//! bindgen's bindings of `cpp/opensubdiv/shim.h` (allowlist `surfkit_osd_*`).

#![allow(
    non_upper_case_globals,
    non_camel_case_types,
    non_snake_case,
    dead_code
)]

include!(concat!(env!("OUT_DIR"), "/opensubdiv_shim.rs"));
