// apitrace's trace format, read by oovr's reader (scene/formats/apitrace.h),
// on files written by tests/apitrace_writer.h; the round-trip test of
// tests/cli/trace_roundtrip.sh reads a file apitrace itself wrote.
#include <gtest/gtest.h>

#include "apitrace_writer.h"
#include "oovr/core/error.h"
#include "oovr/scene/formats/apitrace.h"
#include "test_util.h"

namespace oovr {
namespace {

using apitrace::Call;
using apitrace::Reader;
using apitrace::Value;
using test::TraceWriter;

std::vector<Call> read_all(Reader& r) {
  std::vector<Call> calls;
  Call c;
  while (r.next(c)) calls.push_back(c);
  return calls;
}

std::vector<Call> read_all(const std::string& file, apitrace::ReaderLimits limits = {}) {
  Reader r(file, "test.trace", limits);
  return read_all(r);
}

// A frame of a GL 1.x game: a client array, an indexed draw and the swap.
TraceWriter two_frames() {
  TraceWriter w;
  for (int frame = 0; frame < 2; ++frame) {
    const std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::vector<uint16_t> indices = {0, 1, 2};
    w.gl_client_array("glVertexPointer", 3, "GL_FLOAT", 0x1406, xyz);
    w.call("glDrawElements", {{"mode", w.e("GL_TRIANGLES", 4)},
                              {"count", w.i(3)},
                              {"type", w.e("GL_UNSIGNED_SHORT", 0x1403)},
                              {"indices", w.blob(indices)}});
    w.call("glXSwapBuffers", {{"dpy", w.opaque(0x1234)}, {"drawable", w.u(77)}});
  }
  return w;
}

TEST(Apitrace, ReadsCallsArgumentsAndFrameEnds) {
  Reader r(two_frames().finish(), "test.trace");
  EXPECT_EQ(r.version(), 6u);
  EXPECT_EQ(r.semantic_version(), 6u);
  ASSERT_EQ(r.properties().size(), 1u);
  EXPECT_EQ(r.properties()[0].second, "test");
  const auto calls = read_all(r);
  ASSERT_EQ(calls.size(), 6u);
  for (size_t k = 0; k < calls.size(); ++k) EXPECT_EQ(calls[k].no, k);
  EXPECT_EQ(calls[0].name(), "glVertexPointer");
  EXPECT_TRUE(calls[0].fake());
  EXPECT_FALSE(calls[1].fake());
  EXPECT_EQ(calls[0].arg(0).integer(), 3);
  EXPECT_EQ(*calls[0].arg(1).sig->name_of(calls[0].arg(1).i), "GL_FLOAT");
  EXPECT_EQ(calls[0].arg(3).kind, Value::Kind::blob);
  ASSERT_EQ(calls[0].arg(3).bytes.size(), 36u);
  float x1;
  std::memcpy(&x1, calls[0].arg(3).bytes.data() + 12, 4);
  EXPECT_EQ(x1, 1.0f);
  EXPECT_EQ(calls[1].arg(3).bytes.size(), 6u);
  EXPECT_EQ(calls[1].arg(0).integer(), 4);
  EXPECT_FALSE(calls[1].ends_frame());
  EXPECT_TRUE(calls[2].ends_frame());
  EXPECT_EQ(calls[2].arg(0).kind, Value::Kind::opaque);
  EXPECT_EQ(calls[2].arg(0).u, 0x1234u);
  EXPECT_TRUE(calls[5].ends_frame());
  EXPECT_FALSE(r.truncated());
  EXPECT_THROW(calls[2].arg(2), Error);
}

TEST(Apitrace, ChunkBoundariesCarryNoMeaning) {
  const TraceWriter w = two_frames();
  const auto whole = read_all(w.finish());
  for (size_t chunk : {1, 2, 7, 64}) {
    const auto split = read_all(w.finish(chunk));
    ASSERT_EQ(split.size(), whole.size()) << chunk;
    for (size_t k = 0; k < split.size(); ++k) {
      EXPECT_EQ(split[k].name(), whole[k].name());
      ASSERT_EQ(split[k].args.size(), whole[k].args.size());
      for (size_t a = 0; a < split[k].args.size(); ++a) EXPECT_EQ(split[k].args[a].bytes, whole[k].args[a].bytes);
    }
  }
}

TEST(Apitrace, DecodesEveryValueType) {
  TraceWriter w;
  std::string wide(1, '\x0f');
  TraceWriter::put_uint(wide, 2);
  TraceWriter::put_uint(wide, 'h');
  TraceWriter::put_uint(wide, 0x20AC);  // the euro sign
  w.call("f",
         {{"null", w.null()},
          {"t", w.boolean(true)},
          {"neg", w.i(-5)},
          {"big", w.u(uint64_t(1) << 63)},
          {"fl", w.f(0.25f)},
          {"db", w.d(-1.5)},
          {"s", w.str("hello")},
          {"arr", w.array({w.i(1), w.f(2.0f), w.array({w.i(3)})})},
          {"w", wide}},
         w.i(-7));
  const auto calls = read_all(w.finish());
  ASSERT_EQ(calls.size(), 1u);
  const Call& c = calls[0];
  EXPECT_EQ(c.arg(0).kind, Value::Kind::null);
  EXPECT_EQ(c.arg(1).integer(), 1);
  EXPECT_EQ(c.arg(2).integer(), -5);
  EXPECT_EQ(c.arg(3).u, uint64_t(1) << 63);
  EXPECT_EQ(c.arg(4).number(), 0.25);
  EXPECT_EQ(c.arg(5).number(), -1.5);
  EXPECT_EQ(c.arg(6).bytes, "hello");
  ASSERT_EQ(c.arg(7).items.size(), 3u);
  EXPECT_EQ(c.arg(7).items[1].number(), 2.0);
  EXPECT_EQ(c.arg(7).items[2].items[0].integer(), 3);
  EXPECT_EQ(c.arg(8).bytes, "h\xE2\x82\xAC");
  EXPECT_EQ(c.ret.integer(), -7);
}

TEST(Apitrace, OlderVersionsHaveNoThreadsOrProperties) {
  for (unsigned version : {2u, 3u, 5u}) {
    TraceWriter w(version);
    w.call("glEnable", {{"cap", w.e("GL_BLEND", 0x0BE2)}});
    w.call("glXSwapBuffers", {});
    Reader r(w.finish(), "old.trace");
    EXPECT_EQ(r.version(), version);
    EXPECT_TRUE(r.properties().empty());
    const auto calls = read_all(r);
    ASSERT_EQ(calls.size(), 2u) << version;
    EXPECT_EQ(calls[0].arg(0).integer(), 0x0BE2) << version;
    EXPECT_TRUE(calls[1].ends_frame());
  }
}

TEST(Apitrace, CallsCompleteInLeaveOrderAcrossThreads) {
  TraceWriter w;
  const uint64_t a = w.enter("glFinish", {}, false, 0);
  const uint64_t b = w.enter("glFlush", {}, false, 1);
  w.leave(b);
  w.leave(a);
  w.leave(99);  // a LEAVE of no known call is dropped, as apitrace does
  const auto calls = read_all(w.finish());
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_EQ(calls[0].name(), "glFlush");
  EXPECT_EQ(calls[0].thread, 1u);
  EXPECT_EQ(calls[0].no, 1u);
  EXPECT_EQ(calls[1].name(), "glFinish");
}

TEST(Apitrace, SkippedBlobsKeepTheirSize) {
  Reader r(two_frames().finish(), "test.trace");
  r.read_blobs(false);
  const auto calls = read_all(r);
  ASSERT_EQ(calls.size(), 6u);
  EXPECT_TRUE(calls[0].arg(3).skipped);
  EXPECT_TRUE(calls[0].arg(3).bytes.empty());
  EXPECT_EQ(calls[0].arg(3).u, 36u);
}

TEST(Apitrace, AKilledGamesTraceKeepsItsWholeCalls) {
  const std::string file = two_frames().finish();
  // Cut inside the last chunk (the whole stream is one chunk here, so
  // split it first): the calls before the cut stand.
  const std::string split = two_frames().finish(16);
  for (size_t cut : {split.size() - 3, split.size() - 20}) {
    Reader r(split.substr(0, cut), "cut.trace");
    const auto calls = read_all(r);
    EXPECT_TRUE(r.truncated()) << cut;
    EXPECT_LT(calls.size(), 6u) << cut;
    EXPECT_GE(calls.size(), 4u) << cut;
    for (size_t k = 0; k < calls.size(); ++k) EXPECT_EQ(calls[k].no, k);
  }
  // An ENTER without its LEAVE: returned, flagged incomplete.
  TraceWriter w;
  w.call("glFlush", {});
  w.enter("glFinish", {});
  const auto calls = read_all(w.finish());
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_TRUE(calls[1].flags & apitrace::kIncomplete);
}

void expect_refused(const std::string& file, const std::string& words, apitrace::ReaderLimits limits = {}) {
  try {
    Reader r(file, "bad.trace", limits);
    read_all(r);
    ADD_FAILURE() << "accepted; expected an error with: " << words;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.trace"), std::string::npos) << e.what();
  }
}

std::string stream_of(const std::string& body) {
  std::string s;
  TraceWriter::put_uint(s, 6);
  TraceWriter::put_uint(s, 6);
  TraceWriter::put_uint(s, 0);
  return s + body;
}

TEST(Apitrace, RefusesOtherContainersAndBadChunks) {
  expect_refused("", "empty");
  expect_refused(std::string("\x1f\x8b\x08\x00", 4), "gzip");
  expect_refused(std::string("\x28\xb5\x2f\xfd", 4), "zstd");
  expect_refused("BZh9", "not apitrace's snappy container");
  expect_refused("at", "holds no trace");
  expect_refused(std::string("at\xff\xff\xff\x7f", 6), "more than apitrace ever writes");
  expect_refused(std::string("at\x03\x00\x00\x00\xff\xff\xff", 9), "snappy");
  // A block that decodes to more than apitrace's 1 MiB chunks.
  const std::string big(2 << 20, 'x');
  expect_refused(TraceWriter::container(big, big.size()), "more than apitrace's chunks");
}

TEST(Apitrace, RefusesMalformedStreams) {
  std::string v7;
  TraceWriter::put_uint(v7, 7);
  expect_refused(TraceWriter::container(v7), "format version 7");
  expect_refused(TraceWriter::container(stream_of(std::string(1, '\0') + std::string(11, '\xff'))), "longer than");
  expect_refused(TraceWriter::container(stream_of("\x07")), "unknown event 7");
  // ENTER, thread 0, a new function 4 named "f" with no arguments, an
  // argument detail with an unknown value tag 0x20.
  std::string enter(
      "\x00\x00\x04\x01"
      "f"
      "\x00"
      "\x01\x00\x20",
      9);
  expect_refused(TraceWriter::container(stream_of(enter)), "unknown value type 32");
  std::string bad_detail(
      "\x00\x00\x04\x01"
      "f"
      "\x00"
      "\x09",
      7);
  expect_refused(TraceWriter::container(stream_of(bad_detail)), "unknown call detail 9");
  // A function id far beyond any apitrace writes.
  std::string huge_id("\x00\x00\xff\xff\xff\xff\x0f", 7);
  expect_refused(TraceWriter::container(stream_of(huge_id)), "function id");
}

TEST(Apitrace, EveryDeclaredSizeIsBounded) {
  TraceWriter w;
  std::string deep;
  for (int k = 0; k < 80; ++k) deep += std::string("\x0b\x01", 2);
  deep += TraceWriter::u(1);
  w.call("f", {{"x", deep}});
  expect_refused(w.finish(), "nested more than 64");

  TraceWriter s;
  s.call("f", {{"x", s.str(std::string(100, 'a'))}});
  apitrace::ReaderLimits small;
  small.string_bytes = 50;
  expect_refused(s.finish(), "a string of 100 bytes", small);

  TraceWriter b;
  b.call("f", {{"x", b.blob(std::vector<uint8_t>(100))}});
  small.blob_bytes = 64;
  expect_refused(b.finish(), "a blob of 100 bytes", small);

  TraceWriter a;
  std::vector<std::string> items(30, a.u(1));
  a.call("f", {{"x", a.array(items)}});
  small.count = 20;
  expect_refused(a.finish(), "an array's length of 30", small);

  // A blob that claims more bytes than the file holds is a cut-off call,
  // not an allocation of what it claims.
  std::string claim(
      "\x00\x00\x04\x01"
      "f"
      "\x01\x01x"
      "\x01\x00\x08",
      11);
  TraceWriter::put_uint(claim, uint64_t(200) << 20);
  Reader r(TraceWriter::container(stream_of(claim)), "claim.trace");
  EXPECT_TRUE(read_all(r).empty());
  EXPECT_TRUE(r.truncated());
}

}  // namespace
}  // namespace oovr
