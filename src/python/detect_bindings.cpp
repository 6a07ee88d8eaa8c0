// patlab.detect, read_frame and render: vision::FrameDetector, the call `patlab detect` makes, on
// a numpy (H, W, 3) uint8 image read through the buffer protocol with any strides, and its
// results as the CLI's CSV and JSON; the scene renderer of `patlab render`.
#include <cstdint>
#include <cstring>
#include <optional>

#include "patlab/camera/image.h"
#include "patlab/core/error.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
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

// camera::Image owns its pixels (packed rows), so the frame is copied into one, row by row and
// pixel by pixel when the buffer's strides are not packed; numpy makes no copy before.
camera::Image ToImage(const py::buffer_info& info) {
  camera::Image image =
      camera::Image::Rgb(static_cast<int>(info.shape[1]), static_cast<int>(info.shape[0]));
  const auto* base = static_cast<const uint8_t*>(info.ptr);
  const py::ssize_t sy = info.strides[0], sx = info.strides[1], sc = info.strides[2];
  for (int y = 0; y < image.height_px; ++y) {
    uint8_t* row = image.Row(y);
    const uint8_t* in = base + y * sy;
    if (sx == 3 && sc == 1) {
      std::memcpy(row, in, static_cast<size_t>(image.RowBytes()));
      continue;
    }
    for (int x = 0; x < image.width_px; ++x) {
      for (int c = 0; c < 3; ++c) row[3 * x + c] = in[x * sx + c * sc];
    }
  }
  return image;
}

// One frame through the detector with the thresholds, calibration and (optional) detector
// settings files: (CSV, JSON) as `patlab detect` writes them; with `blobs` the calibrated blobs.
py::tuple Detect(const py::buffer& frame, const std::string& thresholds,
                 const std::string& calibration, const std::string& settings,
                 const std::string& name, bool blobs) {
  const py::buffer_info info = RgbBuffer(frame);
  vision::FrameDetectorOptions options;
  std::optional<detect::DetectorConfig> config;
  if (!settings.empty()) {
    config = formats::LoadDetectorSettings(settings);
    vision::ApplyFrameSettings(formats::LoadFrameSettings(settings), &options);
  }
  vision::FrameDetector frames(formats::LoadThresholds(thresholds),
                               formats::LoadCalibration(calibration), std::move(config), options);
  vision::FrameResultsWriter writer(frames, blobs);
  {
    const py::gil_scoped_release nogil;
    writer.Add(frames.Detect(ToImage(info), name));
  }
  return py::make_tuple(writer.Csv(), writer.Json(), frames.warnings());
}

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
  m.def("_detect", &Detect, py::arg("image"), py::arg("thresholds"), py::arg("calibration"),
        py::arg("settings"), py::arg("name"), py::arg("blobs"));
  m.def("_read_frame", &ReadFrame, py::arg("path"));
  m.def("_render", &Render, py::arg("scene"));
  // The address the detector reads an image from: the buffer's own (tests/python check it).
  m.def("_image_address",
        [](const py::buffer& image) { return reinterpret_cast<uintptr_t>(RgbBuffer(image).ptr); });
}

}  // namespace patlab::python
