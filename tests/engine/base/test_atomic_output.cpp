// The atomic-output facility (engine/base/atomic_output.h; docs/errors.md,
// "Outputs"): a commit group's outputs appear all together or none, the
// temporary file is created exclusively and never through a link, an output
// that is a symbolic link is refused, and every failure removes the
// temporary files.

#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using bristle::AtomicOutput;
using bristle::CommitGroup;
using bristle::Error;
using bristle::ExitCode;
using bristle::writeFileAtomically;
using bristle::testing::TempDir;

namespace {

std::vector<std::string> listing(const TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path())) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string tempOf(const std::string& path) { return path + ".tmp-" + std::to_string(::getpid()); }

template <class F>
Error expectError(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  FAIL("no bristle::Error thrown");
  return Error(ExitCode::kSoftware, "");
}

}  // namespace

TEST_CASE("atomic output: a commit group renames all its outputs, or none", "[atomic]") {
  TempDir dir;
  const std::string a = dir.write("a.txt", "old a"), b = dir.file("b.txt");
  SECTION("all written: all renamed together at the group's commit") {
    CommitGroup group;
    writeFileAtomically(a, "new a");
    writeFileAtomically(b, "new b");
    CHECK(contents(a) == "old a");  // not before the group commits
    CHECK(!fs::exists(b));
    group.commit();
    CHECK(contents(a) == "new a");
    CHECK(contents(b) == "new b");
    CHECK(listing(dir) == std::vector<std::string>{"a.txt", "b.txt"});
  }
  SECTION("the second fails: the first is not renamed and its temporary file is gone") {
    {
      CommitGroup group;
      writeFileAtomically(a, "new a");
      const Error e = expectError([&] { writeFileAtomically(dir.file("no/b.txt"), "new b"); });
      CHECK(e.code() == ExitCode::kCantCreate);
    }
    CHECK(contents(a) == "old a");
    CHECK(listing(dir) == std::vector<std::string>{"a.txt"});
  }
  SECTION("a group inside another hands its outputs on; the outer one renames") {
    CommitGroup outer;
    {
      CommitGroup inner;
      writeFileAtomically(b, "new b");
      inner.commit();
    }
    CHECK(!fs::exists(b));
    outer.commit();
    CHECK(contents(b) == "new b");
  }
}

TEST_CASE("atomic output: what runs at a group's commit runs after its renames, or never",
          "[atomic]") {
  TempDir dir;
  const std::string a = dir.file("a.txt");
  bool ran = false, a_was_there = false;
  SECTION("committed") {
    CommitGroup group;
    writeFileAtomically(a, "a");
    group.atCommit([&] {
      ran = true;
      a_was_there = fs::exists(a);
    });
    group.commit();
    CHECK(ran);
    CHECK(a_was_there);
  }
  SECTION("not committed") {
    {
      CommitGroup group;
      writeFileAtomically(a, "a");
      group.atCommit([&] { ran = true; });
    }
    CHECK(!ran);
    CHECK(listing(dir).empty());
  }
}

TEST_CASE("atomic output: without a group, commit renames at once", "[atomic]") {
  TempDir dir;
  const std::string a = dir.write("a.txt", "old");
  AtomicOutput out(a);
  out.stream() << "new";
  CHECK(fs::exists(tempOf(a)));
  out.commit();
  CHECK(contents(a) == "new");
  CHECK(listing(dir) == std::vector<std::string>{"a.txt"});
}

TEST_CASE("atomic output: the temporary file is created exclusively, never through a link",
          "[atomic]") {
  TempDir dir;
  const std::string victim = dir.write("victim.txt", "victim");
  const std::string out_path = dir.file("o.txt");
  SECTION("a symbolic link planted at the temporary name") {
    fs::create_symlink("victim.txt", tempOf(out_path));
  }
  SECTION("a hard link planted at the temporary name") {
    fs::create_hard_link(victim, tempOf(out_path));
  }
  writeFileAtomically(out_path, "output");
  CHECK(contents(victim) == "victim");
  CHECK(contents(out_path) == "output");
  CHECK(!fs::is_symlink(out_path));
  CHECK(listing(dir) == std::vector<std::string>{"o.txt", "victim.txt"});
}

TEST_CASE("atomic output: an output that is a symbolic link is refused", "[atomic]") {
  TempDir dir;
  const std::string target = dir.write("target.txt", "target");
  const std::string link = dir.file("link.txt"), dangling = dir.file("dangling.txt");
  fs::create_symlink("target.txt", link);
  fs::create_symlink("missing.txt", dangling);
  for (const std::string& path : {link, dangling}) {
    const Error e = expectError([&] { writeFileAtomically(path, "output"); });
    CHECK(e.code() == ExitCode::kCantCreate);
    CHECK(std::string(e.what()) ==
          path + ": cannot create output: is a symbolic link; bristle never writes through a "
                 "link nor replaces it (name the file itself)");
  }
  CHECK(contents(target) == "target");
  CHECK(fs::read_symlink(link) == "target.txt");
  CHECK(listing(dir) == std::vector<std::string>{"dangling.txt", "link.txt", "target.txt"});
}

TEST_CASE("atomic output: a failed write or an abandoned output leaves no temporary file",
          "[atomic]") {
  TempDir dir;
  const std::string a = dir.write("a.txt", "old");
  SECTION("abandoned before commit") {
    AtomicOutput out(a);
    out.stream() << "new";
  }
  SECTION("a write over the file size limit (as a full disk): kIoError") {
    // SIGXFSZ ignored, a write past RLIMIT_FSIZE fails with EFBIG instead.
    struct sigaction ignore {}, old_action {};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGXFSZ, &ignore, &old_action);
    rlimit old_limit{};
    ::getrlimit(RLIMIT_FSIZE, &old_limit);
    rlimit small = old_limit;
    small.rlim_cur = 4096;
    ::setrlimit(RLIMIT_FSIZE, &small);
    const Error e = expectError([&] { writeFileAtomically(a, std::string(100000, 'x')); });
    ::setrlimit(RLIMIT_FSIZE, &old_limit);
    ::sigaction(SIGXFSZ, &old_action, nullptr);
    CHECK(e.code() == ExitCode::kIoError);
    CHECK(std::string(e.what()) == a + ": write failed: File too large");
  }
  CHECK(contents(a) == "old");
  CHECK(listing(dir) == std::vector<std::string>{"a.txt"});
}
