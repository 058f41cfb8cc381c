// libFuzzer target: apitrace trace files (scene/formats/apitrace.h). The
// first byte picks what the rest is: even, the decompressed event stream,
// put into snappy chunks of 1 + byte/2 bytes (so that the fuzzer explores
// the events, signatures and values, and their splitting across chunks);
// odd, a whole file as it would be on disk (the container). Bad input must
// be an Error, never a crash, a hang or an allocation beyond the reader's
// bounds (kept small here, so that a leak of one shows).
#include <cstddef>
#include <cstdint>
#include <string>

#include "../tests/apitrace_writer.h"
#include "oovr/core/error.h"
#include "oovr/scene/formats/apitrace.h"

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
  return 0;
}
