// libFuzzer target: apitrace trace files (scene/formats/apitrace.h) and
// the OpenGL interpreter over them (scene/formats/gl_trace.h). The
// first byte picks what the rest is: even, the decompressed event stream,
// put into snappy chunks of 1 + byte/2 bytes (so that the fuzzer explores
// the events, signatures and values, and their splitting across chunks);
// odd, a whole file as it would be on disk (the container). Bad input must
// be an Error, never a crash, a hang or an allocation beyond the reader's
// bounds (kept small here, so that a leak of one shows).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "../tests/apitrace_writer.h"
#include "oovr/core/error.h"
#include "oovr/scene/formats/apitrace.h"
#include "oovr/scene/formats/gl_trace.h"

// Small bounds, so that a texture or a draw the size of a real one is the
// most an input can make.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  setenv("OOVR_LIMITS", "image_texels=1048576,scene_bytes=64MB,elements=1048576", 1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  const std::string file = data[0] % 2 == 0 ? oovr::test::TraceWriter::container(rest, 1 + data[0] / 2) : rest;
  oovr::apitrace::ReaderLimits limits;
  limits.blob_bytes = 1 << 20;
  limits.call_values = 1 << 14;
  try {
    oovr::apitrace::Reader r(file, "fuzz.trace", limits);
    r.read_blobs(data[0] % 4 < 2);
    oovr::apitrace::Call c;
    while (r.next(c)) {
      for (const auto& a : c.args) (void)a.number();
      if (c.ends_frame()) (void)c.name();
    }
  } catch (const oovr::Error&) {
  }
  try {
    // The first two frames as a scene: every call the interpreter models,
    // with whatever arguments the fuzzer gives them.
    oovr::GlTraceWindow w;
    w.count = 2;
    (void)oovr::import_gl_trace_bytes(file, "fuzz.trace", w);
  } catch (const oovr::Error&) {
  }
  return 0;
}
