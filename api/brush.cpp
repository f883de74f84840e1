#include "bristle/brush.h"

#include <algorithm>
#include <memory>

#include "api/model.h"
#include "engine/formats/brush_library.h"
#include "engine/formats/brush_reader.h"

namespace bristle::api {

ErrorCategory categoryOf(ExitCode code) {
  switch (code) {
    case ExitCode::kUsage: return ErrorCategory::kUsage;
    case ExitCode::kDataError: return ErrorCategory::kDataError;
    case ExitCode::kNoInput: return ErrorCategory::kNoInput;
    case ExitCode::kCantCreate: return ErrorCategory::kCantCreate;
    case ExitCode::kIoError: return ErrorCategory::kIoError;
    default: return ErrorCategory::kSoftware;
  }
}

Brush Brush::load(const std::string& name_or_path) {
  return translateErrors([&] {
    // A name as the command line's --brush takes it (engine/formats/brush_library.h).
    const std::string file = isBrushName(name_or_path)
                                 ? findBrushByName(name_or_path, "Brush::load " + name_or_path)
                                 : name_or_path;
    auto model = std::make_shared<Model>(Model{loadBrush(file), file});
    return Brush(std::move(model));
  });
}

const std::string& Brush::name() const { return model_->brush.name; }
const std::string& Brush::path() const { return model_->path; }
int Brush::spineCount() const { return static_cast<int>(model_->brush.spines.size()); }
double Brush::reachMm() const { return model_->brush.reachMm(); }

double Brush::hairLengthMm() const {
  double longest = 0;
  for (const SpineSpec& s : model_->brush.spines) longest = std::max(longest, s.lengthMm());
  return longest;
}

void setBrushLibraryDirs(const std::vector<std::string>& dirs) {
  bristle::setBrushLibraryDirs(dirs);
}

}  // namespace bristle::api
