#include "cli/measure_plot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "engine/base/temp_files.h"
#include "engine/base/text_file.h"

extern char** environ;

namespace bristle::cli {
namespace {

namespace fs = std::filesystem;

std::string gnuplotMissing(const std::string& option) {
  return option + ": gnuplot not found on PATH (Debian: apt install gnuplot-nox; "
                  "scripts/install-deps installs it)";
}

// A title as gnuplot may read it inside double quotes: gnuplot substitutes
// `command` (backquotes) and reads \ and @ as markup, so only letters, digits
// and a few harmless marks pass; anything else becomes '_'.
std::string safeTitle(const std::string& s) {
  std::string out;
  for (const char c : s)
    out += (std::isalnum(static_cast<unsigned char>(c)) != 0 ||
            std::strchr(" .,:;-+=()/%", c) != nullptr)
               ? c
               : '_';
  return out;
}

// A private folder removed with what it holds, its files registered so that a
// signal removes them too (engine/base/temp_files.h).
class TempFolder {
 public:
  TempFolder() {
    // The folder's name goes into gnuplot's script in quotes: a TMPDIR with
    // anything but plain path characters is passed over for /tmp.
    const char* env = std::getenv("TMPDIR");
    std::string base = env != nullptr && *env != '\0' ? env : "/tmp";
    const char* plain = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789/._-";
    if (base.find_first_not_of(plain) != std::string::npos) base = "/tmp";
    std::string tmpl = base + "/bristle-plot-XXXXXX";
    if (::mkdtemp(tmpl.data()) == nullptr)
      throw Error(ExitCode::kCantCreate,
                  tmpl + ": cannot create a temporary folder for the plot: " +
                      std::strerror(errno));
    dir_ = tmpl;
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string file(const std::string& name) {
    const std::string path = dir_ + "/" + name;
    registrations_.push_back(std::make_unique<TempFileRegistration>(path));
    return path;
  }

 private:
  std::string dir_;
  std::vector<std::unique_ptr<TempFileRegistration>> registrations_;
};

void datablock(std::ostream& gp, const std::string& name,
               const std::vector<render::DepthMeasure>& rows) {
  gp << "$" << name << " << EOD\n";
  for (const render::DepthMeasure& m : rows)
    if (m.shape.touched)
      gp << m.depth_mm << "," << m.shape.width_mm << "," << m.shape.drag_mm << ","
         << m.shape.offset_mm << "\n";
  gp << "EOD\n";
}

std::string script(const MeasurePlot& plot, const std::string& png) {
  std::ostringstream gp;
  gp.precision(6);
  gp << "set terminal pngcairo size 1350,420 font \"DejaVu Sans,10\"\n"
     << "set output \"" << png << "\"\nset datafile separator \",\"\n";
  const render::MeasurementTable* t = plot.table;
  if (t != nullptr) {
    gp << "$data << EOD\n";
    for (const render::MeasuredRow& r : t->rows)
      gp << r.depth_mm << "," << r.value[0] << "," << r.value[1] << "," << r.value[2] << "\n";
    gp << "EOD\n";
  }
  for (size_t i = 0; i < plot.curves.size(); ++i)
    datablock(gp, std::string("c").append(std::to_string(i)), plot.curves[i].measures);
  gp << "set multiplot layout 1,3 title \"" << safeTitle(plot.title) << "\"\n"
     << "set grid lc rgb \"#dddddd\"\nset key top left\nset xlabel \"press depth (mm)\"\n"
     << "set ylabel \"mm\"\nset xrange [0:*]\nset yrange [0:*]\n";
  static const char* kColours[] = {"#1c4e80", "#c0392b", "#27ae60", "#8e44ad"};
  const char* names[] = {"width", "drag", "offset"};
  for (int k = 0; k < 3; ++k) {
    gp << "set title \"" << names[k] << "\"\nplot ";
    std::string sep;
    if (t != nullptr && t->has[size_t(k)]) {
      gp << "$data using 1:" << k + 2 << " with points pt 7 ps 0.8 lc rgb \"#000000\" title \""
         << safeTitle(plot.table_title) << "\"";
      sep = ", ";
    }
    for (size_t i = 0; i < plot.curves.size(); ++i) {
      gp << sep << "$c" << i << " using 1:" << k + 2 << " with linespoints lw 2 pt 6 lc rgb \""
         << kColours[i % 4] << "\" title \"" << safeTitle(plot.curves[i].title) << "\"";
      sep = ", ";
    }
    if (sep.empty()) gp << "NaN notitle";
    gp << "\n";
  }
  gp << "unset multiplot\n";
  return gp.str();
}

// Runs gnuplot on the script, without a shell; its stderr into `errors`.
int runGnuplot(const std::string& script_path, const std::string& errors,
               const std::string& option) {
  std::string prog = "gnuplot", arg = script_path;
  char* argv[] = {prog.data(), arg.data(), nullptr};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc == ENOENT) throw Error(ExitCode::kUnavailable, gnuplotMissing(option));
  if (rc != 0)
    throw Error(ExitCode::kUnavailable, option + ": cannot start gnuplot: " + std::strerror(rc));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

}  // namespace

void checkGnuplot(const std::string& option) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':'))
    if (::access(((dir.empty() ? std::string(".") : dir) + "/gnuplot").c_str(), X_OK) == 0)
      return;
  throw Error(ExitCode::kUnavailable, gnuplotMissing(option));
}

void writeMeasurePlot(const std::string& path, const std::string& option, const MeasurePlot& plot) {
  TempFolder tmp;
  const std::string png = tmp.file("plot.png"), gp = tmp.file("plot.gp"),
                    errors = tmp.file("errors.txt");
  {
    std::ofstream out(gp);
    out << script(plot, png);
    if (!out.flush())
      throw Error(ExitCode::kIoError, gp + ": write failed (the plot's script)");
  }
  const int status = runGnuplot(gp, errors, option);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(png)) {
    std::string first;
    std::ifstream err(errors);
    while (first.empty() && std::getline(err, first)) {
    }
    throw Error(ExitCode::kSoftware, option + ": gnuplot failed" +
                                         (first.empty() ? std::string() : ": " + first));
  }
  writeFileAtomically(path, readTextFile(png));
}

}  // namespace bristle::cli
