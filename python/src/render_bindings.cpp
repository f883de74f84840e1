// renderStroke, Canvas and many strokes on several threads (bristle/render.h,
// bristle/png.h). The GIL is released while the engine works: nothing below
// touches a Python object between gil_scoped_release and its end.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bindings.h"
#include "bristle/png.h"

namespace bristle::py_module {

namespace {

void bindOptions(py::module_& m) {
  py::enum_<api::PaintLoad>(m, "PaintLoad")
      .value("solid", api::PaintLoad::kSolid)
      .value("across", api::PaintLoad::kAcross)
      .value("tip", api::PaintLoad::kTip);
  py::enum_<api::PaintMix>(m, "PaintMix")
      .value("km", api::PaintMix::kKubelkaMunk)
      .value("rgb", api::PaintMix::kLinearRgb);
  py::class_<api::RenderOptions>(m, "RenderOptions")
      .def(py::init<>())
      .def_readwrite("paint", &api::RenderOptions::paint)
      .def_readwrite("load", &api::RenderOptions::load)
      .def_readwrite("amount", &api::RenderOptions::amount)
      .def_readwrite("tip_length", &api::RenderOptions::tip_length)
      .def_readwrite("mix", &api::RenderOptions::mix)
      .def_readwrite("paper_colour", &api::RenderOptions::paper_colour)
      .def_readwrite("paper_tooth_mm", &api::RenderOptions::paper_tooth_mm)
      .def_readwrite("paper_scale_mm", &api::RenderOptions::paper_scale_mm)
      .def_readwrite("paper_seed", &api::RenderOptions::paper_seed)
      .def_readwrite("impasto", &api::RenderOptions::impasto)
      .def_readwrite("px_per_mm", &api::RenderOptions::px_per_mm)
      .def_readwrite("solver", &api::RenderOptions::solver)
      .def_readwrite("solver_max_iterations", &api::RenderOptions::solver_max_iterations)
      .def_readwrite("max_step_mm", &api::RenderOptions::max_step_mm)
      .def_readwrite("steady_step_mm", &api::RenderOptions::steady_step_mm)
      .def_readwrite("min_rate_hz", &api::RenderOptions::min_rate_hz)
      .def_readwrite("contact_band_mm", &api::RenderOptions::contact_band_mm)
      .def_readwrite("ipopt_options", &api::RenderOptions::ipopt_options)
      .def_readwrite("threads", &api::RenderOptions::threads);
  m.def("preset_options", &api::presetOptions, py::arg("name"),
        "RenderOptions of a named preset (bristle/render.h, presetOptions)");
}

py::dict imageFacts(const api::Image& image) {
  py::dict d;
  d["px_per_mm"] = image.px_per_mm;
  d["x0_mm"] = image.x0_mm;
  d["y0_mm"] = image.y0_mm;
  return d;
}

// The image and the stroke's facts, as the package's Stroke takes them.
py::tuple strokeTuple(api::RenderResult&& r) {
  py::dict facts = imageFacts(r.image);
  facts["touched"] = r.touched;
  facts["ink_pixels"] = r.ink_pixels;
  facts["paint_laid_mm3"] = r.paint_laid_mm3;
  facts["failed_spine_solves"] = r.failed_spine_solves;
  return py::make_tuple(imageArray(std::move(r.image)), facts);
}

// The OSMesa context of the calling thread, made at its first stroke and
// kept until the thread ends: llvmpipe compiles a context's shaders once,
// a fifth of a small stroke's CPU time when made per stroke (docs/python.md,
// "Speed"). The same pixels as a fresh context (python/tests/test_cli_pixels.py).
api::StrokeRenderer& threadRenderer() {
  thread_local api::StrokeRenderer renderer;
  return renderer;
}

// The OSMesa contexts of render_many's second and later threads, kept
// between calls and lent to one thread at a time: each call starts its
// threads anew, and a context made for each would compile llvmpipe's shaders
// again, about 130 ms of CPU a call (docs/python.md, "Speed"). A context is
// made current on the thread that draws with it (render/gl/gl_context.cpp),
// so a lent one is current only on its borrower or on threads that have ended.
class LentRenderer {
 public:
  LentRenderer() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (idle_.empty()) {
      ++made_;
      renderer_ = std::make_unique<api::StrokeRenderer>();
      return;
    }
    renderer_ = std::move(idle_.back());
    idle_.pop_back();
  }
  ~LentRenderer() {
    std::lock_guard<std::mutex> lock(mutex_);
    idle_.push_back(std::move(renderer_));
  }
  LentRenderer(const LentRenderer&) = delete;
  LentRenderer& operator=(const LentRenderer&) = delete;
  api::StrokeRenderer& get() { return *renderer_; }
  // How many contexts have been made to lend, for the tests.
  static long made() {
    std::lock_guard<std::mutex> lock(mutex_);
    return made_;
  }

 private:
  std::unique_ptr<api::StrokeRenderer> renderer_;
  static inline std::mutex mutex_;
  static inline std::vector<std::unique_ptr<api::StrokeRenderer>> idle_;
  static inline long made_ = 0;
};

py::tuple renderOne(const api::Brush& brush, const api::Trajectory& trajectory,
                    const api::RenderOptions& options) {
  api::RenderResult r;
  {
    py::gil_scoped_release unlocked;
    r = threadRenderer().render(brush, trajectory, options);
  }
  return strokeTuple(std::move(r));
}

// A whole scene file, painted as `bristle render SCENE` paints it; the image
// and the painting's facts, as the package's Painting takes them.
py::tuple renderScene(const std::string& path, bool impasto, int solver_max_iterations,
                      int threads) {
  api::SceneOptions options;
  options.impasto = impasto;
  options.solver_max_iterations = solver_max_iterations;
  options.threads = threads;
  api::SceneResult r;
  {
    py::gil_scoped_release unlocked;
    r = api::renderScene(path, options);
  }
  py::dict facts = imageFacts(r.image);
  facts["paint_laid_mm3"] = r.paint_laid_mm3;
  facts["paint_picked_up_mm3"] = r.paint_picked_up_mm3;
  facts["untouched"] = r.untouched;
  facts["failed_spine_solves"] = r.failed_spine_solves;
  return py::make_tuple(imageArray(std::move(r.image)), facts);
}

// Strokes taken in turn by `threads` threads, each stroke on the thread that
// took it: the calling thread on its own OSMesa context (threadRenderer), the
// others on lent ones (LentRenderer).
// The first failure (by stroke index) is rethrown, prefixed with its index,
// once every thread has stopped.
std::vector<api::RenderResult> renderAll(const std::vector<api::Brush>& brushes,
                                         const std::vector<api::Trajectory>& trajectories,
                                         const api::RenderOptions& options, int threads) {
  const size_t n = trajectories.size();
  std::vector<api::RenderResult> results(n);
  std::vector<std::exception_ptr> errors(n);
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  auto work = [&](api::StrokeRenderer& renderer) {
    for (size_t i; !failed.load() && (i = next.fetch_add(1)) < n;) {
      try {
        results[i] = renderer.render(brushes[brushes.size() == 1 ? 0 : i], trajectories[i],
                                     options);
      } catch (...) {
        errors[i] = std::current_exception();
        failed.store(true);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t)
    pool.emplace_back([&] {
      LentRenderer lent;
      work(lent.get());
    });
  work(threadRenderer());
  for (std::thread& t : pool) t.join();
  for (size_t i = 0; i < n; ++i) {
    if (!errors[i]) continue;
    try {
      std::rethrow_exception(errors[i]);
    } catch (const api::Error& e) {
      throw api::Error(e.category(), "render_many: stroke " + std::to_string(i) + ": " + e.what());
    }
  }
  return results;
}

py::list renderMany(const std::vector<api::Brush>& brushes,
                    const std::vector<api::Trajectory>& trajectories,
                    const api::RenderOptions& options, int threads) {
  std::vector<api::RenderResult> results;
  {
    py::gil_scoped_release unlocked;
    results = renderAll(brushes, trajectories, options, threads);
  }
  py::list out;
  for (api::RenderResult& r : results) out.append(strokeTuple(std::move(r)));
  return out;
}

// A canvas used from one thread at a time: a second thread's stroke waits
// for the first (the GIL is released while a stroke is painted).
struct LockedCanvas {
  std::mutex mutex;
  api::Canvas canvas;
  LockedCanvas(double x0, double y0, int w, int h, const api::RenderOptions& paper)
      : canvas(x0, y0, w, h, paper) {}
};

py::dict addStroke(LockedCanvas& c, const api::Brush& brush, const api::Trajectory& trajectory,
                   const api::RenderOptions& options) {
  api::StrokeFacts f;
  {
    py::gil_scoped_release unlocked;
    const std::lock_guard<std::mutex> lock(c.mutex);
    f = c.canvas.addStroke(brush, trajectory, options);
  }
  py::dict d;
  d["touched"] = f.touched;
  d["paint_laid_mm3"] = f.paint_laid_mm3;
  d["failed_spine_solves"] = f.failed_spine_solves;
  return d;
}

api::Image canvasImage(LockedCanvas& c, bool impasto) {
  py::gil_scoped_release unlocked;
  const std::lock_guard<std::mutex> lock(c.mutex);
  return c.canvas.image(impasto);
}

void bindCanvas(py::module_& m) {
  py::class_<LockedCanvas>(m, "Canvas")
      .def(py::init<double, double, int, int, const api::RenderOptions&>())
      .def("add_stroke", &addStroke)
      .def("dry",
           [](LockedCanvas& c) {
             py::gil_scoped_release unlocked;
             const std::lock_guard<std::mutex> lock(c.mutex);
             c.canvas.dry();
           })
      .def("image",
           [](LockedCanvas& c, bool impasto) {
             api::Image image = canvasImage(c, impasto);
             py::dict facts = imageFacts(image);
             return py::make_tuple(imageArray(std::move(image)), facts);
           })
      .def("save", [](LockedCanvas& c, const std::string& path, bool impasto) {
        const api::Image image = canvasImage(c, impasto);
        py::gil_scoped_release unlocked;
        api::writePng(path, image);
      });
}

// An H x W x 3 uint8 array (checked by the package) written as a PNG.
void writeArrayPng(const std::string& path, const py::array_t<std::uint8_t, py::array::c_style>& a) {
  api::Image image;
  image.height_px = static_cast<int>(a.shape(0));
  image.width_px = static_cast<int>(a.shape(1));
  image.channels = static_cast<int>(a.shape(2));
  image.pixels.assign(a.data(), a.data() + a.size());
  py::gil_scoped_release unlocked;
  api::writePng(path, image);
}

}  // namespace

void bindRender(py::module_& m) {
  bindOptions(m);
  m.def("render_stroke", &renderOne);
  m.def("render_many", &renderMany);
  m.def("_lent_renderers_made", &LentRenderer::made,
        "OSMesa contexts made for render_many's lent threads so far (for the tests)");
  m.def("render_scene", &renderScene);
  m.def("write_png", &writeArrayPng);
  bindCanvas(m);
}

}  // namespace bristle::py_module
