/* The peer benchmark's conventions (../shared/bench/peer-vtk/README.md), so that VTK's
 * vtkFixedPointVolumeRayCastMapper and cube5 cast draw the same frames from the same data:
 * the 24 cameras from one SplitMix64 stream, the transfer-function JSON files, and the two
 * synthetic phantoms of render_vtk.py. */
#ifndef C5_CAST_PEER_H
#define C5_CAST_PEER_H

#include <stddef.h>
#include <stdint.h>

#include "cast.h"

/* 1/sin(15 deg): the bounding sphere just fills the 30-degree view (VTK's ResetCamera). */
#define C5_PEER_DISTANCE_FIT 3.8637033051562732
#define C5_PEER_DISTANCE_HEAVY 2.0
#define C5_PEER_VIEW_ANGLE 30.0

/* Camera i of n (render_vtk.py make_cameras): one SplitMix64 stream seeded with `seed`, two
 * uniform draws per view in view order; eye = C + D d with D = distance_factor * R_bs, focal
 * = C, up0 = (0,0,1) unless |d.z| > 0.99, then (0,1,0); f = -d, right = normalize(f x up0),
 * up = right x f. C and R_bs of the VTK point-data bounds [0,(X-1)sx] x ... */
void c5_peer_cameras(const size_t dims[3], const double spacing[3], int n, uint64_t seed, double distance_factor,
                     double view_angle_deg, c5_cast_camera *out);

/* A TF file of the peer's format ("opacity", "color", "shading", "opacity_unit_distance_voxels";
 * "name", "description", "scalar_range", "interpolation", "background" accepted and checked
 * where they matter: interpolation must be "linear", background black). unit_distance in
 * the result is in voxels times min_spacing (world units). Errors name the file and key. */
int c5_peer_tf_parse(const char *json_text, const char *label, double min_spacing, c5_tf_desc *out, c5_err *err);
/* "default" or "ml" (the peer's tf_default.json, tf_ml.json, built in), or a path. */
int c5_peer_tf_load(const char *name_or_path, double min_spacing, c5_tf_desc *out, c5_err *err);

typedef enum { C5_PHANTOM_ML, C5_PHANTOM_SHELL } c5_phantom;
/* render_vtk.py synthetic_volume(n, kind): n^3 uint8, x fastest. Returns a malloc'd buffer,
 * or NULL when n < 2, n > 2048 or out of memory. Computed in float32 operation for operation
 * as numpy 1.24 does it, but with libm's sinf/cosf: the shell phantom equals render_vtk.py's
 * byte for byte at n = 64 and 256, ml at n = 64 too; ml at n = 256 differs by one in 64 of
 * its voxels (numpy's float32 cosine differs from libm's by an ulp for some arguments). */
uint8_t *c5_phantom_make(c5_phantom kind, size_t n);
int c5_phantom_parse(const char *s, c5_phantom *out);

#endif
