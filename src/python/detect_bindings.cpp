// patlab.detect, read_frame and render: vision::FrameDetector, the call `patlab detect` makes, on
// a numpy (H, W, 3) uint8 image read in place through the buffer protocol with any strides (a
// camera::ImageView of the array's memory: no copy), and its results as the CLI's CSV and JSON;
// the scene renderer of `patlab render`; `patlab setup` (formats::SetupCamera) with its report.
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>

#include "patlab/camera/image.h"
#include "patlab/core/error.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/data_path.h"
#include "patlab/render/scene_render.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/frame_results.h"
#include "patlab/vision/thresholds_blobs.h"
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

// `patlab setup` (formats::SetupCamera): frames (paths, or (H, W, 3) uint8 arrays named frame0,
// frame1, ...) and already resolved fields and settings; the files are written into `out`
// atomically; the report as a dict.
py::dict SetupTry(const formats::SetupFieldTry& t) {
  py::dict d;
  d["field"] = t.field;
  d["fitted"] = t.fitted && t.failure.empty();
  d["score_px"] = t.score_px;
  d["screen_px"] = t.screen_px;
  d["held_out_mapping_mm"] = t.held_out_mapping_mm;
  d["same_as"] = t.same_as;
  d["screen_view_of"] = t.screen_view_of;
  d["failure"] = t.failure;
  return d;
}

py::dict SetupHeightReport(const formats::SetupHeight& h) {
  py::dict height;
  height["decided_by"] = h.decided_by;
  height["height_mm"] = h.height_mm;
  height["focal_px"] = h.focal_px;
  height["sd_mm"] = h.sd_mm;
  height["robots"] = h.robots;
  height["lines_height_mm"] = h.lines_height_mm;
  height["lines_focal_px"] = h.lines_focal_px;
  height["lines_sd_mm"] = h.lines_sd_mm;
  height["lines_robots"] = h.lines_robots;
  py::list scan;
  for (const formats::SetupHeightTry& t : h.scan) {
    py::dict d;
    d["height_mm"] = t.height_mm;
    d["focal_px"] = t.focal_px;
    d["robots"] = t.robots;
    scan.append(d);
  }
  height["scan"] = scan;
  return height;
}

py::dict SetupFewLinesReport(const formats::SetupFewLines& f) {
  py::dict few;
  few["used"] = f.used;
  few["lines_failure"] = f.lines_failure;
  few["floor_mm_per_px"] = f.floor_mm_per_px;
  few["small_patches"] = f.small_patches;
  few["robots"] = f.robots;
  few["placements"] = f.placements;
  few["on_field"] = f.on_field;
  few["crossing"] = f.crossing;
  few["score_px"] = f.score_px;
  few["runner_up_px"] = f.runner_up_px;
  few["position_sd_mm"] = f.position_sd_mm;
  few["limit_mm"] = f.limit_mm;
  return few;
}

py::list ColourClassesReport(const std::vector<vision::AutoClassFit>& classes_fit) {
  py::list classes;
  for (const vision::AutoClassFit& c : classes_fit) {
    py::dict d;
    d["name"] = c.name;
    d["pixels"] = c.pixels;
    d["blobs"] = c.blobs;
    d["separability"] = c.separability;
    d["nearest"] = c.nearest;
    d["widened_levels"] =
        py::make_tuple(c.widened_levels[0], c.widened_levels[1], c.widened_levels[2]);
    d["thin_alike"] = c.thin_alike;
    classes.append(d);
  }
  return classes;
}

py::dict SetupReport(const formats::SetupResult& r) {
  py::dict out;
  out["binning"] = r.binning;
  out["frame_size_px"] = py::make_tuple(r.frame_size_px[0], r.frame_size_px[1]);
  out["field"] = r.field.name;
  out["from_landmarks"] = r.from_landmarks;
  py::list tried;
  for (const formats::SetupFieldTry& t : r.tried) tried.append(SetupTry(t));
  out["tried"] = tried;
  py::list undecided;
  for (const formats::SetupRival& u : r.undecided) {
    py::dict d;
    d["field"] = u.field;
    d["score_px"] = u.score_px;
    d["floor_difference_mm"] = u.floor_difference_mm;
    d["robots"] = u.robots;
    undecided.append(d);
  }
  out["undecided"] = undecided;
  out["robots_decided"] = r.robots_decided;
  out["lines_overruled"] = r.lines_overruled;
  out["camera_height"] = SetupHeightReport(r.height);
  out["few_lines"] = SetupFewLinesReport(r.few_lines);
  out["mapping_error_mm"] = r.mapping_error_mm;
  out["mapping_resolution_mm"] = r.mapping_resolution_mm;
  out["mapping_error_source"] = r.mapping_error_source;
  out["floor_sd_mm"] = r.floor_sd_mm;
  out["mm_per_px"] = r.mm_per_px;
  out["smallest_patch_px"] = r.smallest_patch_px;
  out["carpet_pixels"] = r.thresholds.carpet.pixels;
  const std::array<int, 3>& noise = r.thresholds.noise_levels;
  out["colour_noise_levels"] = py::make_tuple(noise[0], noise[1], noise[2]);
  out["colour_classes"] = ColourClassesReport(r.thresholds.classes);
  out["colour_fit"] = r.colour_fit;
  out["robots_by_blobs"] = r.robots_by_blobs;
  out["segment_k"] = r.segment_k;
  out["standout_delta_e"] = r.standout_delta_e;
  py::list fits;
  for (const formats::SetupResult::BlobFitTry& t : r.blob_fits)
    fits.append(py::make_tuple(t.standout_delta_e, t.segment_k, t.robots));
  out["blob_fits"] = fits;
  out["robots_by_pixels"] = r.robots_by_pixels;
  const detect::DetectorOptions& t = r.tolerances;
  py::dict tolerances;
  tolerances["patch_sigma_mm"] = t.patch_sigma_mm;
  tolerances["reach_margin_mm"] = t.reach_margin_mm;
  tolerances["area_ratio_min"] = t.area_ratio_min;
  tolerances["area_ratio_max"] = t.area_ratio_max;
  out["tolerances"] = tolerances;
  out["report"] = formats::SetupReportText(r);
  out["seconds"] = r.seconds;
  return out;
}

py::dict Setup(const py::list& frames, const std::string& field, const std::string& binary_dir,
               const std::string& settings, const std::string& out,
               const std::vector<std::string>& landmarks, double robot_height_mm,
               std::optional<double> camera_height_mm, double line_width_px,
               const std::map<std::string, double>& colour_options, int binning) {
  formats::SetupOptions options;
  // A family's every model, or one model (a shipped name or a file), as `patlab setup` reads it.
  formats::SetupFieldModels models =
      formats::SetupFields(field, io::DataRoots(binary_dir, std::getenv("PATLAB_DATA")));
  options.fields = std::move(models.fields);
  options.lenders = std::move(models.lenders);
  options.settings_path = settings;
  options.robot_height_mm = robot_height_mm;
  options.camera_height_mm = camera_height_mm;
  options.line_width_px = line_width_px;
  options.binning = binning;
  for (const std::string& l : landmarks) options.landmarks.push_back(formats::ParseLandmark(l));
  for (const auto& [name, value] : colour_options) {
    vision::SetBlobThresholdsOption(name, value, &options.colours);
  }
  vision::Validate(options.colours);
  const std::filesystem::path dir(out);
  io::CheckWritable({(dir / "setup.toml").string()});
  std::vector<camera::Image> images;
  std::vector<std::string> names;
  for (const py::handle& f : frames) {
    if (py::isinstance<py::str>(f)) {
      const std::string path = f.cast<std::string>();
      images.push_back(vision::ReadFrame(path));
      names.push_back(std::filesystem::path(path).filename().string());
    } else {
      images.push_back(camera::ToRgb(ViewOf(RgbBuffer(f.cast<py::buffer>()))));
      names.push_back("frame" + std::to_string(names.size()));
    }
  }
  std::vector<const camera::Image*> pointers;
  for (const camera::Image& f : images) pointers.push_back(&f);
  formats::SetupResult r;
  {
    const py::gil_scoped_release nogil;
    r = formats::SetupCamera(pointers, names, options);
  }
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& [name, text] : r.files) files.emplace_back((dir / name).string(), text);
  io::WriteFilesAtomic(files);
  py::dict report = SetupReport(r);
  // The robots each frame shows through the files just written, as `patlab setup` prints them.
  const formats::SetupFiles written = formats::LoadSetupFiles(out);
  vision::FrameDetector detector =
      LoadFrameDetector(written.thresholds, written.calibration, written.settings);
  const std::vector<std::string>& palette = detector.detector().config().palette;
  py::list robots;
  for (size_t i = 0; i < images.size(); ++i) {
    py::list in_frame;
    for (const detect::Detection& d : detector.Detect(images[i], names[i]).detections) {
      py::dict robot;
      robot["team"] = d.team_colour >= 0 ? palette[static_cast<size_t>(d.team_colour)] : "?";
      robot["id"] = d.id;
      robot["x_mm"] = d.pose.x_mm;
      robot["y_mm"] = d.pose.y_mm;
      robot["theta_rad"] = d.pose.theta_rad;
      in_frame.append(robot);
    }
    py::dict frame;
    frame["frame"] = names[i];
    frame["robots"] = in_frame;
    robots.append(frame);
  }
  report["robots"] = robots;
  return report;
}

// Pixels (N x 2) to the floor plane at a height (mm; NaN: the calibration's default height)
// through a calibration file: (N x 2) mm, NaN where a pixel's ray does not reach the plane.
py::array_t<double> PixelToFloor(
    const std::string& calibration_path,
    const py::array_t<double, py::array::c_style | py::array::forcecast>& pixels,
    double height_mm) {
  if (pixels.ndim() != 2 || pixels.shape(1) != 2)
    throw InputError("pixels: expected an (N, 2) array of (u, v) in px");
  const camera::Calibration calibration = formats::LoadCalibration(calibration_path);
  const double height = std::isnan(height_mm) ? calibration.default_height_mm : height_mm;
  const py::ssize_t n = pixels.shape(0);
  py::array_t<double> out({n, static_cast<py::ssize_t>(2)});
  const auto in = pixels.unchecked<2>();
  auto mm = out.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const std::optional<Vec2> world =
        calibration.camera.PixelToWorld(Vec2(in(i, 0), in(i, 1)), height);
    mm(i, 0) = world ? world->x() : std::nan("");
    mm(i, 1) = world ? world->y() : std::nan("");
  }
  return out;
}

}  // namespace

void BindDetect(py::module_& m) {
  m.def("_pixel_to_floor", &PixelToFloor, py::arg("calibration"), py::arg("pixels"),
        py::arg("height_mm"));
  m.def("_setup", &Setup, py::arg("frames"), py::arg("field"), py::arg("binary_dir"),
        py::arg("settings"), py::arg("out"), py::arg("landmarks"), py::arg("robot_height_mm"),
        py::arg("camera_height_mm"), py::arg("line_width_px"), py::arg("colour_options"),
        py::arg("binning"));
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
