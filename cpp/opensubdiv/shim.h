/* surfkit's plain-C shim over OpenSubdiv (Far). Opaque handles, POD structs of counts and
 * pointers, an int status (0 = success) plus an error message that the caller frees once
 * with surfkit_osd_free_message. Every function catches all C++ exceptions. bindgen reads
 * this header only. */
#ifndef SURFKIT_OSD_SHIM_H
#define SURFKIT_OSD_SHIM_H

#ifdef __cplusplus
extern "C" {
#endif

/* OpenSubdiv's version as major*10000 + minor*100 + patch (e.g. 30500). */
int surfkit_osd_version(void);

/* Refines a cube once (Catmull–Clark, uniform) and checks the refined counts: a health
 * check that the library links and runs. Returns 0, or non-zero with *error set. */
int surfkit_osd_self_test(char** error);

/* Frees a message returned by the shim (NULL is allowed). */
void surfkit_osd_free_message(char* message);

#ifdef __cplusplus
}
#endif

#endif
