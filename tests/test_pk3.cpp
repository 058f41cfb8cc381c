// The pk3 file system: engine order (later archives override earlier ones),
// case-insensitive paths, and clear errors for corrupt archives.
#include <gtest/gtest.h>
#include <zip.h>

#include <filesystem>
#include <fstream>

#include "oovr/core/error.h"
#include "oovr/scene/formats/pk3.h"
#include "temp_dir.h"

namespace oovr {
namespace {
namespace fs = std::filesystem;

class Pk3Dir : public ::testing::Test {
 protected:
  void archive(const std::string& name, const std::vector<std::pair<std::string, std::string>>& files) {
    int err = 0;
    zip_t* z = zip_open((m_dir / name).c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    ASSERT_NE(z, nullptr);
    for (const auto& [path, text] : files) {
      zip_source_t* src = zip_source_buffer(z, text.data(), text.size(), 0);
      ASSERT_GE(zip_file_add(z, path.c_str(), src, ZIP_FL_OVERWRITE), 0);
    }
    ASSERT_EQ(zip_close(z), 0);
  }
  std::string text(const Pk3FileSystem& fs, const std::string& path) {
    const auto b = fs.read(path);
    return b ? std::string(b->begin(), b->end()) : "<none>";
  }
  test::TempDir m_tmp;
  const fs::path& m_dir = m_tmp.path();
};

TEST_F(Pk3Dir, LaterArchivesOverrideEarlierOnes) {
  archive("pak0.pk3", {{"scripts/a.shader", "old"}, {"Textures/Wall.TGA", "wall"}, {"maps/m1.bsp", "x"}});
  archive("pak1-maps.pk3", {{"scripts/a.shader", "new"}, {"maps/m2.bsp", "y"}});
  archive("PAK0b.pk3", {{"scripts/a.shader", "middle"}});
  const Pk3FileSystem fs(m_dir.string());
  ASSERT_EQ(fs.archives().size(), 3u);
  EXPECT_EQ(fs::path(fs.archives()[1]).filename(), "PAK0b.pk3") << "sorted without regard to case";
  EXPECT_EQ(text(fs, "scripts/a.shader"), "new");
  EXPECT_EQ(text(fs, "textures/wall.tga"), "wall") << "paths match whatever their case";
  EXPECT_EQ(text(fs, "TEXTURES\\WALL.tga"), "wall") << "and whatever their separators";
  EXPECT_EQ(text(fs, "missing"), "<none>");
  EXPECT_EQ(fs.list("maps/", ".bsp"), (std::vector<std::string>{"maps/m1.bsp", "maps/m2.bsp"}));
  EXPECT_NE(fs.archive_of("maps/m2.bsp").find("pak1-maps.pk3"), std::string::npos);
}

// A stored (uncompressed) entry whose bytes changed: its CRC no longer
// matches, and reading it is an error naming it, not the changed bytes.
TEST_F(Pk3Dir, EntriesWithABadCrcAreErrors) {
  const std::string body = "the quick brown fox jumps over the lazy dog";
  {
    int err = 0;
    zip_t* z = zip_open((m_dir / "pak0.pk3").c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    ASSERT_NE(z, nullptr);
    zip_source_t* src = zip_source_buffer(z, body.data(), body.size(), 0);
    const zip_int64_t i = zip_file_add(z, "a.txt", src, ZIP_FL_OVERWRITE);
    ASSERT_GE(i, 0);
    ASSERT_EQ(zip_set_file_compression(z, zip_uint64_t(i), ZIP_CM_STORE, 0), 0);
    ASSERT_EQ(zip_close(z), 0);
  }
  {
    const Pk3FileSystem fs(m_dir.string());
    EXPECT_EQ(text(fs, "a.txt"), body);
  }
  std::fstream f(m_dir / "pak0.pk3", std::ios::in | std::ios::out | std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t at = bytes.find("quick");
  ASSERT_NE(at, std::string::npos);
  f.seekp(std::streamoff(at));
  f.put('Q');
  f.close();
  const Pk3FileSystem fs(m_dir.string());
  try {
    (void)fs.read("a.txt");
    ADD_FAILURE() << "a changed entry was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'a.txt' in archive"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("CRC"), std::string::npos) << e.what();
  }
}

TEST_F(Pk3Dir, CorruptArchivesAreNamed) {
  archive("pak0.pk3", {{"a.txt", std::string(5000, 'a')}});
  const fs::path good = m_dir / "pak0.pk3";
  const auto size = fs::file_size(good);
  // Truncated: the central directory is gone.
  fs::resize_file(good, size / 2);
  try {
    Pk3FileSystem fs(m_dir.string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pak0.pk3"), std::string::npos) << e.what();
  }
  // Not a zip at all.
  std::ofstream(good, std::ios::trunc) << "this is not a zip file";
  EXPECT_THROW(Pk3FileSystem fs(m_dir.string()), Error);
}

TEST_F(Pk3Dir, CorruptEntryDataIsNamed) {
  archive("pak0.pk3", {{"a.txt", std::string(5000, 'a') + std::string(3000, 'b')}});
  // Flip bytes inside the compressed data (after the 30-byte local header
  // and the name): the CRC check or the inflater refuses it.
  {
    std::fstream f(m_dir / "pak0.pk3", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(40);
    f.write("\xff\x00\xff\x00\xff", 5);
  }
  const Pk3FileSystem fs(m_dir.string());
  try {
    fs.read("a.txt");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.txt"), std::string::npos) << e.what();
  }
}

TEST_F(Pk3Dir, DirectoryProblemsAreNamed) {
  EXPECT_THROW(Pk3FileSystem fs((m_dir / "nope").string()), Error);
  EXPECT_THROW(Pk3FileSystem fs(m_dir.string()), Error);  // no archives
}

}  // namespace
}  // namespace oovr
