#pragma once
// Every test's scratch space: a fresh folder under the system temp dir
// (mkdtemp, so parallel ctest runs never share one), removed with all it
// holds when the object goes out of scope -- unless the environment sets
// BRISTLE_KEEP_TEST_FILES, for looking at what a test rendered: then it
// stays, and its path is printed on stderr.

#include <stdlib.h>  // mkdtemp

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace bristle::testing {

class TempDir {
 public:
  // The folder is named <temp>/<prefix>-XXXXXX.
  explicit TempDir(const std::string& prefix = "bristle-test") {
    std::string tmpl = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp failed: " + tmpl);
    path_ = tmpl;
  }
  ~TempDir() {
    if (std::getenv("BRISTLE_KEEP_TEST_FILES") != nullptr) {
      std::cerr << "kept " << path_.string() << "\n";
      return;
    }
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // The path of `name` inside the folder (which need not exist yet).
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  // Writes `text` byte for byte to `name`, making its folders; returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = path_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }

 private:
  std::filesystem::path path_;
};

}  // namespace bristle::testing
