#include "oovr/scene/formats/apitrace.h"

#include <snappy.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <unordered_map>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/text.h"

namespace oovr::apitrace {

namespace {

// The snappy container (docs/apitrace-format.md, section 1): 'a' 't', then
// chunks of a 4-byte little-endian compressed length and a raw snappy
// block. apitrace's writer compresses 1 MiB buffers, so a longer block
// (snappy's MaxCompressedLength(1 MiB) = 1,223,370 bytes) or a larger
// decoded chunk is not a file apitrace wrote.
constexpr uint32_t kChunkBytes = 1u << 20;
constexpr uint32_t kMaxCompressedChunk = 32 + kChunkBytes + kChunkBytes / 6;
constexpr unsigned kMaxVersion = 6;

// Event, detail and value codes (trace_format.hpp).
enum : uint8_t { kEnter = 0, kLeave = 1 };
enum : uint8_t { kDetailEnd = 0, kDetailArg = 1, kDetailRet = 2, kDetailBacktrace = 4, kDetailFlags = 5 };
enum : uint8_t {
  kNull = 0,
  kFalse,
  kTrue,
  kSint,
  kUint,
  kFloat,
  kDouble,
  kString,
  kBlob,
  kEnum,
  kBitmask,
  kArray,
  kStruct,
  kOpaque,
  kRepr,
  kWstring
};

// Functions whose call ends a frame (trace_parser_flags.cpp: SWAPBUFFERS
// and END_FRAME); the DXGI Present family is left out with Direct3D.
bool ends_frame(const std::string& name) {
  static const char* const kNames[] = {
      "CGLFlushDrawable",         "eglSwapBuffers",        "eglSwapBuffersWithDamageEXT", "eglSwapBuffersWithDamageKHR",
      "glFrameTerminatorGREMEDY", "glXSwapBuffers",        "glXSwapBuffersMscOML",        "wglSwapBuffers",
      "wglSwapLayerBuffers",      "wglSwapMultipleBuffers"};
  for (const char* n : kNames)
    if (name == n) return true;
  return false;
}

void append_utf8(std::string& out, uint64_t c) {
  if (c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) c = 0xFFFD;
  if (c < 0x80) {
    out += char(c);
  } else if (c < 0x800) {
    out += char(0xC0 | (c >> 6));
    out += char(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    out += char(0xE0 | (c >> 12));
    out += char(0x80 | ((c >> 6) & 0x3F));
    out += char(0x80 | (c & 0x3F));
  } else {
    out += char(0xF0 | (c >> 18));
    out += char(0x80 | ((c >> 12) & 0x3F));
    out += char(0x80 | ((c >> 6) & 0x3F));
    out += char(0x80 | (c & 0x3F));
  }
}

}  // namespace

const std::string* EnumSig::name_of(int64_t value) const {
  for (const auto& [n, v] : values)
    if (v == value) return &n;
  return nullptr;
}

double Value::number() const {
  switch (kind) {
    case Kind::sint:
    case Kind::boolean:
    case Kind::enumeration: return double(i);
    case Kind::uint:
    case Kind::bitmask:
    case Kind::opaque: return double(u);
    case Kind::real: return d;
    default: return 0;
  }
}

int64_t Value::integer() const {
  switch (kind) {
    case Kind::sint:
    case Kind::boolean:
    case Kind::enumeration: return i;
    case Kind::uint:
    case Kind::bitmask:
    case Kind::opaque: return int64_t(u);
    case Kind::real: return d >= -9.2e18 && d <= 9.2e18 ? int64_t(d) : 0;
    default: return 0;
  }
}

const Value& Call::arg(size_t index) const {
  if (index >= args.size())
    throw Error("call " + std::to_string(no) + " " + name() + " has no argument " + std::to_string(index));
  return args[index];
}

struct Reader::Impl {
  std::string name;
  ReaderLimits limits;
  // Where the compressed bytes come from: a file read chunk by chunk, or
  // bytes in memory.
  std::FILE* file = nullptr;
  std::string memory;
  size_t memory_at = 0;
  uint64_t file_offset = 0;  // of the next compressed chunk
  // The current decompressed chunk and the logical stream's offset of its start.
  std::string chunk, compressed;
  size_t at = 0;
  uint64_t chunk_start = 0;
  bool eof = false;

  unsigned version = 0, semantic = 0;
  std::vector<std::pair<std::string, std::string>> properties;
  bool copy_blobs = true;
  std::function<bool(const FunctionSig&)> blobs_of;  // when set, decides per call
  bool copy_now = true;                              // for the event being read

  std::unordered_map<uint64_t, std::shared_ptr<const FunctionSig>> functions;
  std::unordered_map<uint64_t, std::shared_ptr<const EnumSig>> enums;
  std::unordered_map<uint64_t, uint64_t> structs;  // id -> members
  std::unordered_map<uint64_t, bool> bitmasks;     // ids seen
  std::unordered_map<uint64_t, bool> frames;       // backtrace frame ids seen
  uint64_t next_call = 0;
  std::map<uint64_t, Call> open;  // entered, not left
  bool draining = false;
  bool truncated = false;                    // the stream ended inside an event
  uint64_t call_values = 0, call_bytes = 0;  // of the event being read

  ~Impl() {
    if (file) std::fclose(file);
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error("apitrace file '" + name + "': " + what + " (at byte " + std::to_string(chunk_start + at) +
                " of the decompressed stream)");
  }

  // Reads `n` compressed bytes; false at a clean end.
  bool read_raw(char* out, size_t n) {
    if (file) {
      const size_t got = std::fread(out, 1, n, file);
      file_offset += got;
      if (got != n) {
        if (std::ferror(file)) throw Error("apitrace file '" + name + "': read failed at byte " + std::to_string(file_offset));
        return false;
      }
      return true;
    }
    if (memory.size() - memory_at < n) {
      file_offset += memory.size() - memory_at;
      memory_at = memory.size();
      return false;
    }
    std::memcpy(out, memory.data() + memory_at, n);
    memory_at += n;
    file_offset += n;
    return true;
  }

  // Decompresses the next chunk; false at the end of the file.
  bool next_chunk() {
    if (eof) return false;
    chunk_start += chunk.size();
    chunk.clear();
    at = 0;
    unsigned char len_bytes[4];
    const uint64_t chunk_offset = file_offset;
    if (!read_raw(reinterpret_cast<char*>(len_bytes), 4)) {
      eof = true;  // apitrace too ends at a short length (trace_file_snappy.cpp)
      return false;
    }
    const uint32_t len =
        uint32_t(len_bytes[0]) | uint32_t(len_bytes[1]) << 8 | uint32_t(len_bytes[2]) << 16 | uint32_t(len_bytes[3]) << 24;
    const std::string where = "apitrace file '" + name + "': the compressed chunk at byte " + std::to_string(chunk_offset);
    if (len == 0) {
      eof = true;
      return false;
    }
    if (len > kMaxCompressedChunk)
      throw Error(where + " claims " + std::to_string(len) + " bytes, more than apitrace ever writes (" +
                  std::to_string(kMaxCompressedChunk) + ")");
    compressed.resize(len);
    if (!read_raw(compressed.data(), len)) {
      // What a game killed while it was traced leaves: the calls before it stand.
      truncated = true;
      eof = true;
      return false;
    }
    size_t size = 0;
    if (!snappy::GetUncompressedLength(compressed.data(), len, &size)) throw Error(where + " is not a snappy block");
    if (size > kChunkBytes)
      throw Error(where + " decompresses to " + std::to_string(size) + " bytes, more than apitrace's chunks of " +
                  std::to_string(kChunkBytes));
    if (size == 0) throw Error(where + " is empty: apitrace never writes an empty chunk");
    chunk.resize(size);
    if (!snappy::RawUncompress(compressed.data(), len, chunk.data())) throw Error(where + " is not a valid snappy block");
    return true;
  }

  bool at_end() {
    while (at >= chunk.size())
      if (!next_chunk()) return true;
    return false;
  }

  // The stream ends inside an event: what a game killed while it was being
  // traced leaves. apitrace drops that call and returns the open ones.
  struct Truncated {};

  uint8_t byte() {
    if (at_end()) throw Truncated{};
    return uint8_t(chunk[at++]);
  }

  // LEB128 (trace_writer.cpp): at most 10 bytes for 64 bits.
  uint64_t uint() {
    uint64_t v = 0;
    for (int k = 0; k < 10; ++k) {
      const uint8_t b = byte();
      if (k == 9 && b > 1) fail("a number longer than 64 bits");
      v |= uint64_t(b & 0x7F) << (7 * k);
      if (!(b & 0x80)) return v;
    }
    fail("a number longer than 10 bytes");
  }

  // Copies `n` bytes of the stream into `out` (or skips them).
  void bytes(uint64_t n, std::string* out) {
    // Grown as bytes arrive, not reserved as announced: a short file cannot
    // make a large allocation.
    if (out) out->clear();
    while (n > 0) {
      if (at_end()) throw Truncated{};
      const size_t take = size_t(std::min<uint64_t>(n, chunk.size() - at));
      if (out) out->append(chunk, at, take);
      at += take;
      n -= take;
    }
  }

  std::string string() {
    const uint64_t n = uint();
    if (n > limits.string_bytes)
      fail("a string of " + std::to_string(n) + " bytes, more than " + std::to_string(limits.string_bytes));
    std::string s;
    bytes(n, &s);
    return s;
  }

  uint64_t count(const char* what) {
    const uint64_t n = uint();
    if (n > limits.count) fail(std::string(what) + " of " + std::to_string(n) + ", more than " + std::to_string(limits.count));
    return n;
  }

  uint64_t id(const char* what) {
    const uint64_t n = uint();
    if (n > limits.signature_id)
      fail(std::string(what) + " id " + std::to_string(n) + ", more than " + std::to_string(limits.signature_id));
    return n;
  }

  // A tagged signed integer (enum signature values): SINT or UINT.
  int64_t sint() {
    const uint8_t tag = byte();
    const uint64_t v = uint();
    if (tag == kSint) return v > uint64_t(INT64_MAX) ? INT64_MIN : -int64_t(v);
    if (tag == kUint) return v > uint64_t(INT64_MAX) ? INT64_MAX : int64_t(v);
    fail("an enum value tagged " + std::to_string(tag) + ", not a signed or unsigned number");
  }

  std::shared_ptr<const FunctionSig> function() {
    const uint64_t i = id("function");
    auto it = functions.find(i);
    if (it != functions.end()) return it->second;
    auto sig = std::make_shared<FunctionSig>();
    sig->id = i;
    sig->name = string();
    if (sig->name.empty() || has_control_characters(sig->name)) fail("a function name that is empty or holds control characters");
    const uint64_t n = count("a function's argument count");
    for (uint64_t k = 0; k < n; ++k) sig->arg_names.push_back(string());
    if (ends_frame(sig->name)) sig->flags |= kEndFrame;
    return functions.emplace(i, std::move(sig)).first->second;
  }

  std::shared_ptr<const EnumSig> enumeration() {
    const uint64_t i = id("enum");
    auto it = enums.find(i);
    if (it != enums.end()) return it->second;
    auto sig = std::make_shared<EnumSig>();
    if (version >= 3) {
      const uint64_t n = count("an enum's value count");
      for (uint64_t k = 0; k < n; ++k) {
        std::string nm = string();
        sig->values.emplace_back(std::move(nm), sint());
      }
    } else {
      std::string nm = string();
      sig->values.emplace_back(std::move(nm), sint());
    }
    return enums.emplace(i, std::move(sig)).first->second;
  }

  void value(Value& v, int depth) {
    if (depth > limits.depth) fail("values nested more than " + std::to_string(limits.depth) + " deep");
    if (++call_values > limits.call_values) fail("a call with more than " + std::to_string(limits.call_values) + " values");
    v = Value();
    const uint8_t tag = byte();
    switch (tag) {
      case kNull: return;
      case kFalse:
      case kTrue:
        v.kind = Value::Kind::boolean;
        v.i = tag == kTrue;
        return;
      case kSint: {
        const uint64_t magnitude = uint();
        v.kind = Value::Kind::sint;
        v.i = magnitude > uint64_t(INT64_MAX) ? INT64_MIN : -int64_t(magnitude);
        return;
      }
      case kUint:
        v.kind = Value::Kind::uint;
        v.u = uint();
        return;
      case kFloat: {
        char b[4];
        for (char& c : b) c = char(byte());
        float f;
        std::memcpy(&f, b, 4);
        v.kind = Value::Kind::real;
        v.d = f;
        return;
      }
      case kDouble: {
        char b[8];
        for (char& c : b) c = char(byte());
        std::memcpy(&v.d, b, 8);
        v.kind = Value::Kind::real;
        return;
      }
      case kString:
        v.kind = Value::Kind::string;
        v.bytes = string();
        return;
      case kBlob: {
        const uint64_t n = uint();
        call_bytes += n;
        if (n > limits.blob_bytes || call_bytes > limits.blob_bytes)
          fail("a blob of " + std::to_string(n) + " bytes, more than the " + std::to_string(limits.blob_bytes) +
               " a call may hold");
        v.kind = Value::Kind::blob;
        v.u = n;
        v.skipped = !copy_now;
        bytes(n, copy_now ? &v.bytes : nullptr);
        return;
      }
      case kEnum: {
        v.kind = Value::Kind::enumeration;
        v.sig = enumeration();
        // Before version 3 the value is the signature's one value.
        v.i = version >= 3 ? sint() : v.sig->values.front().second;
        return;
      }
      case kBitmask: {
        const uint64_t i = id("bitmask");
        if (!bitmasks.count(i)) {
          const uint64_t n = count("a bitmask's flag count");
          for (uint64_t k = 0; k < n; ++k) {
            string();
            uint();
          }
          bitmasks[i] = true;
        }
        v.kind = Value::Kind::bitmask;
        v.u = uint();
        return;
      }
      case kArray: {
        const uint64_t n = count("an array's length");
        v.kind = Value::Kind::array;
        for (uint64_t k = 0; k < n; ++k) value(v.items.emplace_back(), depth + 1);
        return;
      }
      case kStruct: {
        const uint64_t i = id("struct");
        auto it = structs.find(i);
        if (it == structs.end()) {
          string();  // the struct's name
          const uint64_t n = count("a struct's member count");
          for (uint64_t k = 0; k < n; ++k) string();
          it = structs.emplace(i, n).first;
        }
        v.kind = Value::Kind::structure;
        for (uint64_t k = 0; k < it->second; ++k) value(v.items.emplace_back(), depth + 1);
        return;
      }
      case kOpaque:
        v.kind = Value::Kind::opaque;
        v.u = uint();
        return;
      case kRepr: {
        Value human;
        value(human, depth + 1);
        value(v, depth + 1);  // the machine value is what the call used
        return;
      }
      case kWstring: {
        const uint64_t n = count("a wide string's length");
        v.kind = Value::Kind::wstring;
        for (uint64_t k = 0; k < n; ++k) append_utf8(v.bytes, uint());
        return;
      }
      default: fail("an unknown value type " + std::to_string(tag));
    }
  }

  void backtrace() {
    const uint64_t n = count("a backtrace's frame count");
    for (uint64_t k = 0; k < n; ++k) {
      const uint64_t i = id("stack frame");
      if (frames.count(i)) continue;
      frames[i] = true;
      for (;;) {
        const uint8_t d = byte();
        if (d == 0) break;
        if (d == 1 || d == 2 || d == 3) string();
        else if (d == 4 || d == 5) uint();
        else fail("an unknown stack frame detail " + std::to_string(d));
      }
    }
  }

  void details(Call& c) {
    call_values = 0;
    call_bytes = 0;
    for (;;) {
      const uint8_t d = byte();
      switch (d) {
        case kDetailEnd: return;
        case kDetailArg: {
          const uint64_t index = uint();
          if (index >= c.sig->arg_names.size() && index >= limits.count)
            fail("argument " + std::to_string(index) + " of " + c.sig->name + ", which has " +
                 std::to_string(c.sig->arg_names.size()));
          if (index >= c.args.size()) c.args.resize(size_t(index) + 1);
          value(c.args[size_t(index)], 0);
          break;
        }
        case kDetailRet: value(c.ret, 0); break;
        case kDetailBacktrace: backtrace(); break;
        case kDetailFlags:
          if (uint() & 1) c.flags |= kFake;
          break;
        default: fail("an unknown call detail " + std::to_string(d) + " in " + c.sig->name);
      }
    }
  }

  void header() {
    try {
      read_header();
    } catch (const Truncated&) {
      throw Error("apitrace file '" + name + "' ends inside its header");
    }
  }

  void read_header() {
    if (at_end()) throw Error("apitrace file '" + name + "' holds no trace");
    const uint64_t v = uint();
    if (v > kMaxVersion)
      fail("format version " + std::to_string(v) + ": oovr reads apitrace's versions 0 to 6 (apitrace 11 writes 6)");
    version = unsigned(v);
    semantic = version;
    if (version >= 6) {
      const uint64_t s = uint();
      if (s > version) fail("semantic version " + std::to_string(s) + " is newer than the format version " + std::to_string(v));
      semantic = unsigned(s);
      for (uint64_t k = 0;; ++k) {
        if (k > limits.count) fail("more than " + std::to_string(limits.count) + " properties");
        std::string key = string();
        if (key.empty()) break;
        properties.emplace_back(std::move(key), string());
      }
    }
  }

  bool next(Call& out) {
    for (;;) {
      if (!draining && at_end()) draining = true;
      if (draining) {
        if (open.empty()) return false;
        out = std::move(open.begin()->second);
        open.erase(open.begin());
        out.flags |= kIncomplete;
        return true;
      }
      try {
        if (event(out)) return true;
      } catch (const Truncated&) {
        truncated = true;
        draining = true;
      }
    }
  }

  // Reads one event; true when it completed a call (into `out`).
  bool event(Call& out) {
    const uint8_t kind = byte();
    if (kind == kEnter) {
      Call c;
      c.thread = version >= 4 ? uint32_t(std::min<uint64_t>(uint(), UINT32_MAX)) : 0;
      c.sig = function();
      copy_now = blobs_of ? blobs_of(*c.sig) : copy_blobs;
      c.flags = c.sig->flags;
      c.args.resize(c.sig->arg_names.size());
      details(c);
      c.no = next_call++;  // only a whole ENTER takes a number (apitrace drops a cut-off one)
      if (open.size() >= limits.open_calls)
        fail("more than " + std::to_string(limits.open_calls) + " calls entered and not left");
      open.emplace(c.no, std::move(c));
      return false;
    }
    if (kind == kLeave) {
      const uint64_t no = uint();
      auto it = open.find(no);
      if (it == open.end()) {
        // apitrace scans and drops a LEAVE of a call it does not know.
        Call dropped;
        dropped.sig = std::make_shared<const FunctionSig>(FunctionSig{0, "(unknown call " + std::to_string(no) + ")", {}, 0});
        details(dropped);
        return false;
      }
      copy_now = blobs_of ? blobs_of(*it->second.sig) : copy_blobs;
      details(it->second);
      out = std::move(it->second);
      open.erase(it);
      return true;
    }
    fail("an unknown event " + std::to_string(kind));
  }
};

namespace {

void check_container(const std::string& name, const unsigned char* head, size_t n) {
  if (n >= 2 && head[0] == 'a' && head[1] == 't') return;
  std::string kind = "neither apitrace's snappy container nor another format apitrace writes";
  if (n >= 2 && head[0] == 0x1f && head[1] == 0x8b)
    kind = "gzip-compressed (an old apitrace container): recompress it with `apitrace repack`";
  else if (n >= 4 && head[0] == 0x28 && head[1] == 0xB5 && head[2] == 0x2F && head[3] == 0xFD)
    kind = "zstd-compressed (apitrace 13 and later): recompress it with `apitrace repack`";
  else if (n >= 1)
    kind = "not apitrace's snappy container (perhaps Brotli, which has no signature): recompress it with `apitrace repack`";
  else kind = "empty";
  throw Error("apitrace file '" + name + "' is " + kind);
}

}  // namespace

Reader::Reader(const std::string& path, ReaderLimits limits) : m(std::make_unique<Impl>()) {
  m->name = path;
  m->limits = limits;
  check_input_file(path, "apitrace file", UINT64_MAX);
  m->file = std::fopen(path.c_str(), "rb");
  if (!m->file) throw Error("cannot open apitrace file '" + path + "': " + std::strerror(errno));
  unsigned char head[4] = {0, 0, 0, 0};
  const size_t n = std::fread(head, 1, 4, m->file);
  check_container(path, head, n);
  std::fseek(m->file, 2, SEEK_SET);
  m->file_offset = 2;
  m->header();
}

Reader::Reader(std::string bytes, const std::string& name, ReaderLimits limits) : m(std::make_unique<Impl>()) {
  m->name = name;
  m->limits = limits;
  check_container(name, reinterpret_cast<const unsigned char*>(bytes.data()), std::min<size_t>(bytes.size(), 4));
  m->memory = std::move(bytes);
  m->memory_at = 2;
  m->file_offset = 2;
  m->header();
}

Reader::~Reader() = default;

unsigned Reader::version() const { return m->version; }
unsigned Reader::semantic_version() const { return m->semantic; }
const std::vector<std::pair<std::string, std::string>>& Reader::properties() const { return m->properties; }
void Reader::read_blobs(bool on) { m->copy_blobs = on; }
void Reader::read_blobs_of(std::function<bool(const FunctionSig&)> wanted) { m->blobs_of = std::move(wanted); }
bool Reader::next(Call& call) { return m->next(call); }
bool Reader::truncated() const { return m->truncated; }
uint64_t Reader::chunk_end() const { return m->file_offset; }

uint64_t cut_trace(const std::string& in, const std::string& out, int last_frame) {
  if (last_frame < 0) throw Error("a trace is cut after a frame numbered 0 or more");
  uint64_t keep = 0;
  {
    Reader r(in);
    r.read_blobs(false);
    Call c;
    int frame = 0;
    while (frame <= last_frame && r.next(c))
      if (c.ends_frame()) ++frame;
    if (frame <= last_frame)
      throw Error("apitrace file '" + in + "' has " + std::to_string(frame) + " frames: it cannot be cut after frame " +
                  std::to_string(last_frame));
    keep = r.chunk_end();
  }
  check_output_path(out, "cut trace");
  const std::string tmp = out + ".part";
  std::FILE* src = std::fopen(in.c_str(), "rb");
  if (!src) throw Error("cannot open apitrace file '" + in + "': " + std::strerror(errno));
  std::FILE* dst = std::fopen(tmp.c_str(), "wb");
  if (!dst) {
    std::fclose(src);
    throw Error("cannot write '" + tmp + "': " + std::strerror(errno));
  }
  std::string buf(1 << 20, '\0');
  uint64_t left = keep;
  bool ok = true;
  while (left > 0 && ok) {
    const size_t n = std::fread(buf.data(), 1, size_t(std::min<uint64_t>(left, buf.size())), src);
    ok = n > 0 && std::fwrite(buf.data(), 1, n, dst) == n;
    left -= n;
  }
  ok = ok && std::fflush(dst) == 0;
  const int err = errno;
  std::fclose(src);
  ok = std::fclose(dst) == 0 && ok;
  if (!ok || std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error("cannot write '" + out + "': " + std::strerror(err ? err : errno));
  }
  return keep;
}
uint64_t Reader::offset() const { return m->chunk_start + m->at; }
const std::string& Reader::name() const { return m->name; }

}  // namespace oovr::apitrace
