#include "haptics/hdapi.h"

#include <dlfcn.h>

#include <cstdlib>

#include "engine/base/error.h"

namespace bristle::haptics::hd {

namespace {

template <typename Fn>
void resolve(void* lib, const std::string& path, const char* name, Fn* out) {
  dlerror();
  void* sym = dlsym(lib, name);
  if (sym == nullptr)
    throw Error(ExitCode::kUnavailable,
                path + ": symbol " + name + " not found: not an OpenHaptics HDAPI library");
  *out = reinterpret_cast<Fn>(sym);
}

}  // namespace

std::string hdLibraryPath() {
  const char* env = std::getenv("BRISTLE_HD_LIBRARY");
  return env != nullptr && *env != '\0' ? env : "libHD.so";
}

HdApi HdApi::load(const std::string& path) {
  // RTLD_NODELETE: the library stays mapped for the life of the process.
  void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
  if (lib == nullptr) {
    const char* why = dlerror();
    throw Error(ExitCode::kUnavailable,
                path + ": cannot load the OpenHaptics library (" + (why ? why : "unknown") +
                    "); set BRISTLE_HD_LIBRARY to its path");
  }
  HdApi api;
#define BRISTLE_HD_RESOLVE(fn) resolve(lib, path, #fn, &api.fn)
  BRISTLE_HD_RESOLVE(hdInitDevice);
  BRISTLE_HD_RESOLVE(hdDisableDevice);
  BRISTLE_HD_RESOLVE(hdMakeCurrentDevice);
  BRISTLE_HD_RESOLVE(hdBeginFrame);
  BRISTLE_HD_RESOLVE(hdEndFrame);
  BRISTLE_HD_RESOLVE(hdGetError);
  BRISTLE_HD_RESOLVE(hdGetErrorString);
  BRISTLE_HD_RESOLVE(hdEnable);
  BRISTLE_HD_RESOLVE(hdDisable);
  BRISTLE_HD_RESOLVE(hdGetDoublev);
  BRISTLE_HD_RESOLVE(hdGetIntegerv);
  BRISTLE_HD_RESOLVE(hdSetDoublev);
  BRISTLE_HD_RESOLVE(hdGetString);
  BRISTLE_HD_RESOLVE(hdStartScheduler);
  BRISTLE_HD_RESOLVE(hdStopScheduler);
  BRISTLE_HD_RESOLVE(hdSetSchedulerRate);
  BRISTLE_HD_RESOLVE(hdScheduleAsynchronous);
  BRISTLE_HD_RESOLVE(hdUnschedule);
  BRISTLE_HD_RESOLVE(hdCheckCalibration);
#undef BRISTLE_HD_RESOLVE
  // Never dlclose: vendor drivers do not survive being unloaded.
  return api;
}

}  // namespace bristle::haptics::hd
