//! Checked views of the caller's pointers: null pointers, lengths whose byte size
//! overflows and invalid UTF-8 become errors naming the argument, never undefined behaviour
//! that Rust could have caught.

use std::ffi::{c_char, CStr};

use crate::status::Failure;

/// `len` elements at `ptr` (any pointer when `len` is 0).
///
/// # Safety
/// `ptr` must point to `len` readable elements when `len > 0`.
pub(crate) unsafe fn slice<'a, T>(
    ptr: *const T,
    len: usize,
    what: &str,
) -> Result<&'a [T], Failure> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(Failure::invalid(format!(
            "{what} is a null pointer but {len} elements were announced"
        )));
    }
    if len
        .checked_mul(std::mem::size_of::<T>())
        .is_none_or(|b| b > isize::MAX as usize)
    {
        return Err(Failure::invalid(format!(
            "{what}: {len} elements exceed the address space"
        )));
    }
    Ok(std::slice::from_raw_parts(ptr, len))
}

/// `len` writable elements at `ptr`.
///
/// # Safety
/// As [`slice`], for writing.
pub(crate) unsafe fn slice_mut<'a, T>(
    ptr: *mut T,
    len: usize,
    what: &str,
) -> Result<&'a mut [T], Failure> {
    if len == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(Failure::invalid(format!(
            "{what} is a null pointer but {len} elements must be written"
        )));
    }
    if len
        .checked_mul(std::mem::size_of::<T>())
        .is_none_or(|b| b > isize::MAX as usize)
    {
        return Err(Failure::invalid(format!(
            "{what}: {len} elements exceed the address space"
        )));
    }
    Ok(std::slice::from_raw_parts_mut(ptr, len))
}

/// The value behind a handle or input struct.
///
/// # Safety
/// `ptr` must be null or point to a live value of `T`.
pub(crate) unsafe fn reference<'a, T>(ptr: *const T, what: &str) -> Result<&'a T, Failure> {
    ptr.as_ref()
        .ok_or_else(|| Failure::invalid(format!("{what} is a null pointer")))
}

/// The caller's output slot.
///
/// # Safety
/// `ptr` must be null or point to writable storage of `T`.
pub(crate) unsafe fn output<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    ptr.as_mut()
        .ok_or_else(|| Failure::invalid(format!("{what} (an output) is a null pointer")))
}

/// Sets the caller's output slot to `empty` (NULL for a handle or a borrowed pointer, 0 or
/// an all-zero struct for a value) when the slot is not null. Every function with outputs
/// calls this first, before anything can fail: a failed call (an error or a caught panic)
/// then leaves its outputs at their empty value, never at a stale handle or pointer of an
/// earlier call that a caller who does not check the status could use.
///
/// # Safety
/// `ptr` must be null or point to writable storage of `T`.
pub(crate) unsafe fn clear<T: Copy>(ptr: *mut T, empty: T) {
    if !ptr.is_null() {
        ptr.write(empty);
    }
}

/// A NUL-terminated UTF-8 string.
///
/// # Safety
/// `ptr` must be null or point to a NUL-terminated string.
pub(crate) unsafe fn text<'a>(ptr: *const c_char, what: &str) -> Result<&'a str, Failure> {
    if ptr.is_null() {
        return Err(Failure::invalid(format!("{what} is a null pointer")));
    }
    CStr::from_ptr(ptr)
        .to_str()
        .map_err(|_| Failure::invalid(format!("{what} is not valid UTF-8")))
}

/// Moves `value` into a new heap handle written to `out`.
pub(crate) fn give<T>(out: &mut *mut T, value: T) {
    *out = Box::into_raw(Box::new(value));
}

/// Frees a handle made by [`give`] (null is ignored).
///
/// # Safety
/// `ptr` must be null or come from [`give`] and not have been freed.
pub(crate) unsafe fn take<T>(ptr: *mut T) {
    if !ptr.is_null() {
        drop(Box::from_raw(ptr));
    }
}
