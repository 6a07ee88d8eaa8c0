// Field lines through a camera: the carpet with the painted lines and arcs of a field
// (calib/field.h, as calib/field_marks.h infers the painted arcs) drawn through a pinhole camera
// with its lens distortion, antialiased by supersampling. A frame with known truth for the
// automatic field calibration (calib/auto_calibrate.h); the sensor of camera_render.h
// (SimulateSensor) adds noise, Bayer and 4:2:2 chroma on top.
#pragma once

#include "patlab/calib/field.h"
#include "patlab/camera/camera.h"
#include "patlab/camera/image.h"
#include "patlab/render/render.h"

namespace patlab::render {

struct FieldLineStyle {
  double line_width_mm = 10.0;  // > 0: the painted width, centred on the model's lines
  Rgb carpet = {40, 110, 40};
  Rgb line = {235, 235, 235};
  Rgb outside = {60, 60, 60};  // where a pixel's ray misses the floor (above the horizon)
  int supersample = 3;         // samples per pixel and axis, in [1, 8]
};

// The RGB frame of `field`'s lines on the carpet through `camera` (a pinhole camera; a
// homography camera or bad style is an InputError).
camera::Image RenderFieldLines(const calib::Field& field, const camera::CameraModel& camera,
                               int width_px, int height_px, const FieldLineStyle& style = {});

}  // namespace patlab::render
