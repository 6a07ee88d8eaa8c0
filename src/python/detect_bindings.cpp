// patlab.detect, read_frame and render: vision::FrameDetector, the call `patlab detect` makes, on
// a numpy (H, W, 3) uint8 image read in place through the buffer protocol with any strides (a
// camera::ImageView of the array's memory: no copy), and its results as the CLI's CSV and JSON;
// the scene renderer of `patlab render`.
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstring>
#include <optional>

#include "patlab/camera/image.h"
#include "patlab/core/error.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/scene_render.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/frame_results.h"
#include "python/bindings.h"

namespace patlab::python {

namespace {

// The image's buffer, checked: 3 dimensions, 3 channels, one unsigned byte each; any strides.
py::buffer_info RgbBuffer(const py::buffer& image) {
  py::buffer_info info = image.request();
  if (info.ndim != 3 || info.shape[2] != 3 || info.itemsize != 1 || info.format != "B") {
    throw InputError("image is not an (H, W, 3) uint8 array (" + std::to_string(info.ndim) +
                     " dimensions, format '" + EscapeForMessage(info.format) +
                     "'); expected RGB bytes, e.g. numpy.zeros((480, 640, 3), numpy.uint8)");
  }
  return info;
}

// The buffer as the view the detector reads: its own memory, its strides (numpy's, in bytes, of
// any sign), no copy.
camera::ImageView ViewOf(const py::buffer_info& info) {
  if (info.shape[0] < 1 || info.shape[1] < 1 || info.shape[0] > INT_MAX ||
      info.shape[1] > INT_MAX) {
    throw InputError("image is " + std::to_string(info.shape[0]) + " x " +
                     std::to_string(info.shape[1]) +
                     " pixels; expected at least one row and one column");
  }
  camera::ImageView view;
  view.data = static_cast<const uint8_t*>(info.ptr);
  view.width_px = static_cast<int>(info.shape[1]);
  view.height_px = static_cast<int>(info.shape[0]);
  view.format = camera::PixelFormat::kRgb8;
  view.row_stride = info.strides[0];
  view.pixel_stride = info.strides[1];
  view.channel_stride = info.strides[2];
  return view;
}

// One frame through the detector with the thresholds, calibration and (optional) detector
// settings files: (CSV, JSON) as `patlab detect` writes them; with `blobs` the calibrated blobs;
// with `explain` the JSON's frame carries "explanations" (detect::KeyDiagnosis, --explain).
// The front end `patlab detect -t -c [-s]` builds from its files.
vision::FrameDetector LoadFrameDetector(const std::string& thresholds,
                                        const std::string& calibration, const std::string& settings,
                                        bool explain = false) {
  vision::FrameDetectorOptions options;
  options.explain = explain;
  std::optional<detect::DetectorConfig> config;
  if (!settings.empty()) {
    config = formats::LoadDetectorSettings(settings);
    vision::ApplyFrameSettings(formats::LoadFrameSettings(settings), &options);
  }
  return vision::FrameDetector(formats::LoadThresholds(thresholds),
                               formats::LoadCalibration(calibration), std::move(config), options);
}

py::tuple Detect(const py::buffer& frame, const std::string& thresholds,
                 const std::string& calibration, const std::string& settings,
                 const std::string& name, bool blobs, bool explain) {
  const py::buffer_info info = RgbBuffer(frame);
  vision::FrameDetector frames = LoadFrameDetector(thresholds, calibration, settings, explain);
  vision::FrameResultsWriter writer(frames, blobs);
  const camera::ImageView view = ViewOf(info);
  {
    const py::gil_scoped_release nogil;
    writer.Add(frames.Detect(view, name));
  }
  return py::make_tuple(writer.Csv(), writer.Json(), frames.warnings());
}

// patlab.Detector: the front end built once from its files, then frame after frame in memory
// (a camera loop in Python) with the detections as numpy columns and no text in between; the
// seconds the C++ call took come back too, so the Python overhead can be measured
// (scripts/bench_python.py).
class Detector {
 public:
  Detector(const std::string& thresholds, const std::string& calibration,
           const std::string& settings)
      : frames_(LoadFrameDetector(thresholds, calibration, settings)) {
    if (!frames_.has_detector()) {
      throw InputError(
          "settings is empty; expected a detector settings file (patterns to "
          "detect), e.g. experiments/detector.toml");
    }
  }

  py::dict Detect(const py::buffer& image, const std::string& name) {
    const camera::ImageView view = ViewOf(RgbBuffer(image));
    const vision::FrameResult* result = nullptr;
    double seconds = 0.0;
    {
      const py::gil_scoped_release nogil;
      const auto start = std::chrono::steady_clock::now();
      result = &frames_.Detect(view, name);
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    const std::vector<detect::Detection>& d = result->detections;
    const py::ssize_t n = static_cast<py::ssize_t>(d.size());
    py::array_t<int32_t> pattern(n), team(n), id(n);
    py::array_t<double> x(n), y(n), theta(n), confidence(n);
    for (py::ssize_t k = 0; k < n; ++k) {
      const detect::Detection& e = d[static_cast<size_t>(k)];
      pattern.mutable_at(k) = e.pattern;
      team.mutable_at(k) = e.team_colour;
      id.mutable_at(k) = e.id;
      x.mutable_at(k) = e.pose.x_mm;
      y.mutable_at(k) = e.pose.y_mm;
      theta.mutable_at(k) = e.pose.theta_rad;
      confidence.mutable_at(k) = e.confidence;
    }
    py::dict out;
    out["pattern"] = pattern;
    out["team_colour"] = team;
    out["id"] = id;
    out["x_mm"] = x;
    out["y_mm"] = y;
    out["theta_rad"] = theta;
    out["confidence"] = confidence;
    out["cpp_seconds"] = seconds;
    return out;
  }

  std::vector<std::string> Patterns() const {
    std::vector<std::string> names;
    for (const auto& p : frames_.detector().config().patterns) names.push_back(p.pattern.name);
    return names;
  }
  std::vector<std::string> Palette() const { return frames_.detector().config().palette; }
  const std::vector<std::string>& Warnings() const { return frames_.warnings(); }

 private:
  vision::FrameDetector frames_;
};

py::array_t<uint8_t> ArrayOfImage(const camera::Image& rgb) {
  py::array_t<uint8_t> out({rgb.height_px, rgb.width_px, 3});
  std::memcpy(out.mutable_data(), rgb.data.data(), rgb.data.size());
  return out;
}

// A PNG, JPEG or PPM frame as an (H, W, 3) uint8 array.
py::array_t<uint8_t> ReadFrame(const std::string& path) {
  return ArrayOfImage(camera::ToRgb(vision::ReadFrame(path)));
}

// `patlab render SCENE` without --camera: the scene file's frame, and its true poses as CSV.
py::tuple Render(const std::string& path) {
  const formats::SceneFile file = formats::LoadSceneFile(path);
  camera::Image frame;
  {
    const py::gil_scoped_release nogil;
    frame = render::RenderScene(file.scene, file.calibration.camera);
  }
  return py::make_tuple(ArrayOfImage(frame), render::TruthCsv(file.scene));
}

}  // namespace

void BindDetect(py::module_& m) {
  py::class_<Detector>(m, "_Detector")
      .def(py::init<const std::string&, const std::string&, const std::string&>(),
           py::arg("thresholds"), py::arg("calibration"), py::arg("settings"))
      .def("detect", &Detector::Detect, py::arg("image"), py::arg("name") = "frame")
      .def_property_readonly("patterns", &Detector::Patterns)
      .def_property_readonly("palette", &Detector::Palette)
      .def_property_readonly("warnings", &Detector::Warnings);
  m.def("_detect", &Detect, py::arg("image"), py::arg("thresholds"), py::arg("calibration"),
        py::arg("settings"), py::arg("name"), py::arg("blobs"), py::arg("explain") = false);
  m.def("_read_frame", &ReadFrame, py::arg("path"));
  // The thresholds, calibration and settings files a `patlab setup` folder names (its
  // setup.toml), as `patlab detect --setup DIR` reads them.
  m.def(
      "_setup_files",
      [](const std::string& dir) {
        const formats::SetupFiles f = formats::LoadSetupFiles(dir);
        return py::make_tuple(f.thresholds, f.calibration, f.settings);
      },
      py::arg("dir"));
  m.def("_render", &Render, py::arg("scene"));
  // The view detect() hands the detector for an image (the same ViewOf): its data address and
  // (height, width, row, pixel and channel strides); tests/python check that it is the array's
  // own memory and strides, i.e. that no copy is made.
  m.def("_image_view", [](const py::buffer& image) {
    const camera::ImageView view = ViewOf(RgbBuffer(image));
    return py::make_tuple(reinterpret_cast<uintptr_t>(view.data), view.height_px, view.width_px,
                          view.row_stride, view.pixel_stride, view.channel_stride);
  });
}

}  // namespace patlab::python
