#pragma once
// bristle/brush.h -- a brush of the library, or of a bristle-brush/1 file
// (docs/formats.md, "Brush"), and the read-only facts a caller sizes a stroke by.
//
//   const bristle::api::Brush round = bristle::api::Brush::load("round");
//   round.spineCount();   // 7
//
// A Brush is immutable and cheap to copy (its model is shared).

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace bristle::api {

class Brush {
 public:
  // A library name ("round": no '/', no .json), looked up in the brush library
  // folders (setBrushLibraryDirs), or a path to a bristle-brush/1 file.
  // Throws Error: kNoInput for an unknown name or a missing file, kDataError
  // naming the file and field for a bad one.
  static Brush load(const std::string& name_or_path);

  const std::string& name() const;        // the file's "name"
  const std::string& path() const;        // the file it was read from
  int spineCount() const;                 // spines (hair tufts) of the model
  double hairLengthMm() const;            // longest spine, root to tip (mm)
  double reachMm() const;                 // furthest any hair reaches from the ferrule centre (mm)

  struct Model;  // the engine's brush, for the API's own sources
  const Model& model() const { return *model_; }

 private:
  explicit Brush(std::shared_ptr<const Model> model) : model_(std::move(model)) {}
  std::shared_ptr<const Model> model_;
};

// The folders a brush name is looked up in, in order, for the whole process
// (as `bristle`'s BRISTLE_BRUSH_PATH; docs/formats.md, "Brush library"). Until
// called: the folders of the environment variable BRISTLE_BRUSH_PATH
// (colon-separated). An installed bristle's library is
// <prefix>/share/bristle/brushes, which find_package(bristle) names as
// ${bristle_BRUSH_LIBRARY_DIR}.
void setBrushLibraryDirs(const std::vector<std::string>& dirs);

}  // namespace bristle::api
