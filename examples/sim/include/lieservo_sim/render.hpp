// lieservo_sim/render.hpp — pictures of the simulated runs: time-lapse stills in the style of
// the paper's photographs, strips of frames and short videos, drawn offscreen with MuJoCo's
// renderer on an OSMesa (software OpenGL) context: no display and no GPU.
//
// Everything is drawn afterwards from the states the tasks logged (mujoco::StateLog, every
// kStatePeriod s), on a model and data of its own: rendering never touches a run, so a run
// with pictures and one without log the same (tests/sim: the identical-logs test).
//
// Built only where OSMesa (Debian: libosmesa6-dev) and OpenCV are found; lieservo_demo says
// once when it has no renderer and writes the plots alone.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mujoco_world.hpp"
#include "tasks.hpp"

namespace lieservo::sim::render {

/// An offscreen context that could not be made, or a picture that could not be drawn.
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// MuJoCo's free camera: it looks at `lookat` (mm, work frame) from `distance` mm away, turned
/// by azimuth about z and tilted by elevation (degrees; −90 looks straight down).
struct View {
  Vec3 lookat = Vec3::Zero();
  double distance = 800;
  double azimuth_deg = 90;
  double elevation_deg = -89.9;
};

/// Drawn on top of the scene, not part of it: a flat disc (the target) ...
struct Marker {
  Vec3 position = Vec3::Zero();  ///< mm, centre of the disc (its axis is z)
  double radius = 10;            ///< mm
  std::array<float, 4> rgba{{0.85f, 0.1f, 0.75f, 1}};
};
/// ... and a polyline of thin capsules (a sensor's path).
struct Path {
  std::vector<Vec3> points;  ///< mm
  double width = 2;          ///< mm
  std::array<float, 4> rgba{{0.85f, 0.1f, 0.75f, 1}};
};

class Renderer {
 public:
  /// An OSMesa context of width × height pixels, used from the thread that draws. Throws
  /// RenderError when none can be made.
  Renderer(int width, int height);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// The log's scene at the states `moments` (indices into log.qpos, oldest first) drawn in one
  /// picture: the last opaque, the earlier ones translucent and fainter the older they are
  /// (fixed scenery once), then the markers and paths. 8-bit BGR, width × height. Throws
  /// RenderError for an empty log, an index out of range or a state of the wrong size.
  cv::Mat draw(const mujoco::StateLog& log, const std::vector<std::size_t>& moments, const View& view,
               const std::vector<Marker>& markers = {}, const std::vector<Path>& paths = {});

  int width() const noexcept { return width_; }
  int height() const noexcept { return height_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_, height_;
};

/// `count` indices spread evenly over a log of `n` states, first and last included.
std::vector<std::size_t> evenMoments(std::size_t n, int count);

/// What the writers below wrote (paths relative to out_dir) and what they could not.
struct Written {
  std::vector<std::string> images, videos;
  std::vector<std::string> problems;  ///< e.g. no video encoder; nothing here fails a run
};

/// The time-lapse still of each pushing case's first trial, `<figure_stem>/<object>.png` under
/// out_dir: the object and the sensors at five moments (earlier ones translucent), the leader's
/// path magenta, the follower's white, the target a magenta disc; from above and at an angle,
/// side by side. With `video`, also `<figure_stem>/<object>.mp4` (or .webm) of the whole trial.
void writePushingPictures(Renderer& renderer, const PushingResult& result, const std::string& out_dir, bool video,
                          Written& written);
/// A strip of six frames of the tracking run (`tracking_errors/frames.png`), and its video.
void writeTrackingPictures(Renderer& renderer, const TrackingResult& result, const std::string& out_dir, bool video,
                           Written& written);
/// Strips of six frames of the ramp and of the first dome path (`following_ramp/frames.png`,
/// `following_dome/frames.png`), and their videos.
void writeFollowingPictures(Renderer& renderer, const FollowingResult& result, const std::string& out_dir, bool video,
                            Written& written);

/// Writes `frames` (BGR, all one size) as a video that browsers play: H.264 in MP4 where
/// OpenCV's FFmpeg has an encoder for it, else VP8 in WebM. `stem` is the path without the
/// extension; returns the extension written (".mp4" or ".webm"), or "" when no encoder opened.
std::string writeVideo(const std::vector<cv::Mat>& frames, double fps, const std::string& stem);

}  // namespace lieservo::sim::render
