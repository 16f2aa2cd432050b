/* Preloaded under Open3D by bench_peers.py: sets every ray's mask to all ones before Embree's
   rtcIntersect1M and rtcOccluded1M run (Open3D leaves it 0; Debian's Embree tests masks). The
   mask is the 32-bit field after org, tnear, dir, time and tfar: byte 36 of RTCRay and RTCRayHit. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef void (*stream_fn)(void*, void*, void*, unsigned, size_t);

/* Embree's own function: Python loads Open3D (and with it Embree) with RTLD_LOCAL, where
   RTLD_NEXT does not look, so the library is asked for by name. */
static stream_fn embree(const char* name) {
  void* lib = dlopen("libembree3.so.3", RTLD_NOW | RTLD_NOLOAD);
  if (!lib) lib = dlopen("libembree3.so.3", RTLD_NOW);
  return lib ? (stream_fn)dlsym(lib, name) : (stream_fn)0;
}

static void set_masks(void* rays, unsigned m, size_t stride) {
  const uint32_t all = 0xFFFFFFFFu;
  for (unsigned i = 0; i < m; ++i) memcpy((char*)rays + (size_t)i * stride + 36, &all, sizeof all);
}

void rtcIntersect1M(void* scene, void* context, void* rayhits, unsigned m, size_t stride) {
  static stream_fn real;
  if (!real) real = embree("rtcIntersect1M");
  set_masks(rayhits, m, stride);
  real(scene, context, rayhits, m, stride);
}

void rtcOccluded1M(void* scene, void* context, void* rays, unsigned m, size_t stride) {
  static stream_fn real;
  if (!real) real = embree("rtcOccluded1M");
  set_masks(rays, m, stride);
  real(scene, context, rays, m, stride);
}
