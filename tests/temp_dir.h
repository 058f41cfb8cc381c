// A fresh directory per test, removed afterwards.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace oovr::test {

class TempDir {
 public:
  TempDir() {
    m_path = std::filesystem::temp_directory_path() /
             ("oovr-test-" + std::to_string(::getpid()) + "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(m_path);
  }
  ~TempDir() { std::filesystem::remove_all(m_path); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return m_path; }
  // The path of `name` in the directory, written with `text` when given.
  std::string file(const std::string& name, const std::string& text = {}) const {
    const std::filesystem::path p = m_path / name;
    if (!text.empty()) std::ofstream(p) << text;
    return p.string();
  }

 private:
  std::filesystem::path m_path;
};

}  // namespace oovr::test
