// lieservo_sim/render.cpp — offscreen pictures of the logged runs (MuJoCo's renderer on OSMesa).
#include "lieservo_sim/render.hpp"

#include <GL/osmesa.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "task_common.hpp"

namespace lieservo::sim::render {

namespace {

constexpr double kMm = 1e-3;            // mm → m (MuJoCo works in metres)
constexpr int kMaxGeoms = 2000;  // the ramp's 102 boxes, 5 moments of the rest, paths and markers fit
constexpr std::size_t kMaxSegments = 60;  // a path is drawn with at most this many capsules
// The target and the paths: colours no object has (tests/sim/check_results_page.py tells the
// objects by colour).
constexpr std::array<float, 4> kMagenta{{0.85f, 0.1f, 0.75f, 1}}, kWhite{{0.95f, 0.95f, 0.95f, 1}};

}  // namespace

struct Renderer::Impl {
  OSMesaContext gl = nullptr;
  std::vector<unsigned char> buffer;  // OSMesa's colour buffer (RGBA)
  std::string mjcf;                   // the scene the model below was built from
  mjModel* m = nullptr;
  mjData* d = nullptr;
  mjvScene scene;
  mjvOption option;
  mjrContext context;
  bool has_scene = false, has_context = false;

  void release() {
    if (has_context) mjr_freeContext(&context);
    if (has_scene) mjv_freeScene(&scene);
    if (d) mj_deleteData(d);
    if (m) mj_deleteModel(m);
    has_context = has_scene = false;
    d = nullptr;
    m = nullptr;
    mjcf.clear();
  }
  void load(const mujoco::SceneSpec& spec, const std::string& text, int width, int height);
  void addMoments(const mujoco::StateLog& log, const std::vector<std::size_t>& moments, mjvCamera& camera);
  void addDecor(const std::vector<Marker>& markers, const std::vector<Path>& paths);
};

Renderer::Renderer(int width, int height) : impl_(std::make_unique<Impl>()), width_(width), height_(height) {
  if (width < 16 || height < 16 || width > 4096 || height > 4096)
    throw RenderError("renderer: the picture must be 16 to 4096 pixels wide and high");
  impl_->gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  if (!impl_->gl) throw RenderError("renderer: OSMesa could not create an OpenGL context");
  impl_->buffer.resize(std::size_t(width) * std::size_t(height) * 4);
  if (!OSMesaMakeCurrent(impl_->gl, impl_->buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
    OSMesaDestroyContext(impl_->gl);
    throw RenderError("renderer: OSMesa could not make its context current");
  }
}

Renderer::~Renderer() {
  if (!impl_) return;
  if (impl_->gl) OSMesaMakeCurrent(impl_->gl, impl_->buffer.data(), GL_UNSIGNED_BYTE, width_, height_);
  impl_->release();
  if (impl_->gl) OSMesaDestroyContext(impl_->gl);
}

// The model, its scene and its GPU context for `spec` (its MJCF text `text`), at the picture's size.
void Renderer::Impl::load(const mujoco::SceneSpec& spec, const std::string& text, int width, int height) {
  release();
  try {
    m = mujoco::loadScene(spec);
  } catch (const SceneError& e) {
    throw RenderError(std::string("renderer: ") + e.what());
  }
  d = mj_makeData(m);
  if (!d) {
    release();
    throw RenderError("renderer: out of memory for the scene's data");
  }
  // Offscreen buffer of the picture's size; no multisampling (llvmpipe draws 4 samples at
  // about 2.5× the time of one); a stronger headlight beside the scene's light, so that the
  // view at an angle is not dark.
  m->vis.global.offwidth = width;
  m->vis.global.offheight = height;
  m->vis.quality.offsamples = 0;
  for (int c = 0; c < 3; ++c) {
    m->vis.headlight.ambient[c] = 0.4f;
    m->vis.headlight.diffuse[c] = 0.5f;
  }
  // Without objects the support bears nothing, and the tracking plate starts in its plane
  // (the two would fight for the same pixels): hide it.
  if (spec.objects.empty())
    if (const int support = mj_name2id(m, mjOBJ_GEOM, "support"); support >= 0) m->geom_group[support] = 5;
  mjv_defaultScene(&scene);
  mjv_makeScene(m, &scene, kMaxGeoms);
  has_scene = true;
  mjv_defaultOption(&option);
  mjr_defaultContext(&context);
  mjr_makeContext(m, &context, mjFONTSCALE_100);
  has_context = true;
  mjr_setBuffer(mjFB_OFFSCREEN, &context);
  if (context.offWidth < width || context.offHeight < height) {
    release();
    throw RenderError("renderer: MuJoCo's offscreen buffer is smaller than the picture");
  }
  mjcf = text;
}

// The newest moment first, with the fixed scenery; then the earlier ones' moving geoms,
// translucent, fading with age.
void Renderer::Impl::addMoments(const mujoco::StateLog& log, const std::vector<std::size_t>& moments,
                                mjvCamera& camera) {
  auto pose = [&](std::size_t k) {
    std::copy(log.qpos[k].begin(), log.qpos[k].end(), d->qpos);
    mj_kinematics(m, d);
  };
  pose(moments.back());
  mjv_updateScene(m, d, &option, nullptr, &camera, mjCAT_ALL, &scene);
  const std::size_t n = moments.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    pose(moments[i]);
    const int first = scene.ngeom;
    mjv_addGeoms(m, d, &option, nullptr, mjCAT_DYNAMIC, &scene);
    const float alpha = 0.2f + 0.35f * float(i) / float(n - 1);
    for (int g = first; g < scene.ngeom; ++g) scene.geoms[g].rgba[3] *= alpha;
  }
}

// The markers (discs) and the paths (capsules), as far as the scene has room for them.
void Renderer::Impl::addDecor(const std::vector<Marker>& markers, const std::vector<Path>& paths) {
  auto addGeom = [&]() -> mjvGeom* {
    if (scene.ngeom >= scene.maxgeom) return nullptr;
    return &scene.geoms[scene.ngeom++];
  };
  for (const Marker& mk : markers) {
    mjvGeom* g = addGeom();
    if (!g) break;
    const mjtNum size[3] = {mk.radius * kMm, mk.radius * kMm, 0.0005};
    const mjtNum pos[3] = {mk.position.x() * kMm, mk.position.y() * kMm, mk.position.z() * kMm};
    mjv_initGeom(g, mjGEOM_CYLINDER, size, pos, nullptr, mk.rgba.data());
    g->category = mjCAT_DECOR;
  }
  for (const Path& p : paths) {
    const std::size_t stride = std::max<std::size_t>(1, p.points.size() / kMaxSegments);
    for (std::size_t k = stride; k < p.points.size(); k += stride) {
      mjvGeom* g = addGeom();
      if (!g) break;
      const Vec3 a = p.points[k - stride] * kMm, b = p.points[k] * kMm;
      mjv_initGeom(g, mjGEOM_CAPSULE, nullptr, nullptr, nullptr, p.rgba.data());
      mjv_makeConnector(g, mjGEOM_CAPSULE, 0.5 * p.width * kMm, a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
      g->category = mjCAT_DECOR;
    }
  }
}

cv::Mat Renderer::draw(const mujoco::StateLog& log, const std::vector<std::size_t>& moments, const View& view,
                       const std::vector<Marker>& markers, const std::vector<Path>& paths) {
  Impl& I = *impl_;
  if (log.empty() || moments.empty()) throw RenderError("renderer: nothing to draw (an empty log)");
  for (std::size_t k : moments)
    if (k >= log.qpos.size()) throw RenderError("renderer: a moment past the end of the log");
  if (!OSMesaMakeCurrent(I.gl, I.buffer.data(), GL_UNSIGNED_BYTE, width_, height_))
    throw RenderError("renderer: OSMesa could not make its context current");

  // The model, its scene and its GPU context, kept while the scene stays the same (a video).
  if (const std::string mjcf = mujoco::sceneMjcf(log.scene); mjcf != I.mjcf) I.load(log.scene, mjcf, width_, height_);
  for (std::size_t k : moments)
    if (log.qpos[k].size() != std::size_t(I.m->nq)) throw RenderError("renderer: a logged state does not fit its scene");

  mjvCamera camera;
  mjv_defaultCamera(&camera);
  camera.type = mjCAMERA_FREE;
  for (int c = 0; c < 3; ++c) camera.lookat[c] = view.lookat[c] * kMm;
  camera.distance = view.distance * kMm;
  camera.azimuth = view.azimuth_deg;
  camera.elevation = view.elevation_deg;

  I.addMoments(log, moments, camera);
  I.addDecor(markers, paths);

  // No shadows: on llvmpipe they double the time of a picture, and the translucent moments
  // read better without them.
  I.scene.flags[mjRND_SHADOW] = 0;
  const mjrRect viewport = {0, 0, width_, height_};
  mjr_render(viewport, &I.scene, &I.context);
  cv::Mat rgb(height_, width_, CV_8UC3);
  mjr_readPixels(rgb.data, nullptr, viewport, &I.context);
  cv::Mat bgr;
  cv::flip(rgb, bgr, 0);  // OpenGL's rows run bottom-up
  cv::cvtColor(bgr, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

std::vector<std::size_t> evenMoments(std::size_t n, int count) {
  std::vector<std::size_t> v;
  if (n == 0 || count < 1) return v;
  if (count == 1 || n == 1) return {n - 1};
  for (int i = 0; i < count; ++i) {
    const std::size_t k = std::size_t(std::lround(double(n - 1) * i / (count - 1)));
    if (v.empty() || k != v.back()) v.push_back(k);
  }
  return v;
}

std::string writeVideo(const std::vector<cv::Mat>& frames, double fps, const std::string& stem) {
  if (frames.empty()) return "";
  const cv::Size size = frames.front().size();
  for (const auto& [ext, fourcc] : {std::pair<const char*, int>{".mp4", cv::VideoWriter::fourcc('a', 'v', 'c', '1')},
                                    std::pair<const char*, int>{".webm", cv::VideoWriter::fourcc('V', 'P', '8', '0')}}) {
    cv::VideoWriter writer;
    if (!writer.open(stem + ext, cv::CAP_FFMPEG, fourcc, fps, size)) continue;
    for (const cv::Mat& f : frames) writer.write(f);
    writer.release();
    return ext;
  }
  return "";
}

namespace {

// A caption across the top of a picture.
void caption(cv::Mat& img, const std::string& text) {
  cv::rectangle(img, cv::Rect(0, 0, img.cols, 26), cv::Scalar(255, 255, 255), cv::FILLED);
  cv::putText(img, text, cv::Point(8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
}

// Frames of a whole log from one view (a state per kStatePeriod s), written as a video played
// at twice the simulated speed.
void video(Renderer& r, const mujoco::StateLog& log, const View& view, const std::vector<Marker>& markers,
           const std::string& out_dir, const std::string& rel_stem, const std::string& title, Written& written) {
  std::vector<cv::Mat> frames;
  for (std::size_t k = 0; k < log.qpos.size(); ++k) {
    cv::Mat f = r.draw(log, {k}, view, markers);
    char t[32];
    std::snprintf(t, sizeof t, "  t = %.1f s", log.times[k]);
    caption(f, title + t);
    frames.push_back(std::move(f));
  }
  const std::string ext = writeVideo(frames, 2.0 / kStatePeriod, detail::join(out_dir, rel_stem));
  if (ext.empty())
    written.problems.push_back(rel_stem + ": no video encoder (H.264/MP4 or VP8/WebM) in this OpenCV");
  else
    written.videos.push_back(rel_stem + ext);
}

void writeImage(const cv::Mat& img, const std::string& out_dir, const std::string& rel, Written& written) {
  const std::string path = detail::join(out_dir, rel);
  makeDirectories(path.substr(0, path.find_last_of('/')));
  // Light compression: a fifth of the default's time, files a third larger.
  if (cv::imwrite(path, img, {cv::IMWRITE_PNG_COMPRESSION, 1})) written.images.push_back(rel);
  else written.problems.push_back(rel + ": could not be written");
}

// Six frames of a log side by side (two rows of three), each captioned with its time.
cv::Mat strip(Renderer& r, const mujoco::StateLog& log, const View& view, const std::string& title) {
  const std::vector<std::size_t> ks = evenMoments(log.qpos.size(), 6);
  std::vector<cv::Mat> frames;
  for (std::size_t k : ks) {
    cv::Mat f = r.draw(log, {k}, view);
    char t[64];
    std::snprintf(t, sizeof t, "%s  t = %.1f s", title.c_str(), log.times[k]);
    caption(f, t);
    frames.push_back(std::move(f));
  }
  while (frames.size() % 3) frames.push_back(cv::Mat(frames.front().size(), CV_8UC3, cv::Scalar(255, 255, 255)));
  std::vector<cv::Mat> rows;
  for (std::size_t i = 0; i < frames.size(); i += 3) {
    cv::Mat row;
    cv::hconcat(std::vector<cv::Mat>(frames.begin() + long(i), frames.begin() + long(i) + 3), row);
    rows.push_back(row);
  }
  cv::Mat out;
  cv::vconcat(rows, out);
  return out;
}

}  // namespace

void writePushingPictures(Renderer& r, const PushingResult& result, const std::string& out_dir, bool with_video,
                          Written& written) {
  for (const PushingCase& pc : result.cases) {
    if (pc.figure_stem.empty() || pc.trials.empty() || pc.trials.front().states.empty()) continue;
    const PushTrial& t = pc.trials.front();
    // Frame everything the trial went through: both sensors, the object, the target.
    Vec2 lo(pc.setup.target), hi(pc.setup.target);
    auto grow = [&](double x, double y) {
      lo = lo.cwiseMin(Vec2(x, y));
      hi = hi.cwiseMax(Vec2(x, y));
    };
    for (const Vec3& p : t.sensor_path) grow(p.x(), p.y());
    for (const Vec3& p : t.follower_path) grow(p.x(), p.y());
    for (const Vec3& p : t.object_path) grow(p.x(), p.y());
    const double reach = pc.setup.object.size + 60;  // the object's and the sensors' extent
    const Vec2 c = 0.5 * (lo + hi);
    const double span = (hi - lo).maxCoeff() + 2 * reach;
    // MuJoCo's default field of view is 45° vertically: the span fits at span / (2 tan 22.5°).
    const double fit = 0.5 * span / std::tan(kPi / 8);
    const double z = 0.5 * std::min(pc.setup.object.height, 120.0);
    const View above{Vec3(c.x(), c.y(), 0), fit, 90, -89.9};
    // At an angle: from behind the start, to the side, looking along the push.
    const Vec2 dir = (pc.setup.target - Vec2(t.sensor_path.front().x(), t.sensor_path.front().y())).normalized();
    const double az = rad2deg(std::atan2(dir.y(), dir.x())) - 35;
    const View angle{Vec3(c.x(), c.y(), z), 0.95 * fit, az, -32};
    const std::vector<Marker> target = {Marker{Vec3(pc.setup.target.x(), pc.setup.target.y(), 0.3), 12, kMagenta}};
    std::vector<Path> paths = {Path{t.sensor_path, 2.5, kMagenta}};
    if (!t.follower_path.empty()) paths.push_back(Path{t.follower_path, 2.5, kWhite});
    const std::vector<std::size_t> ks = evenMoments(t.states.qpos.size(), 5);
    cv::Mat a = r.draw(t.states, ks, above, target, paths), b = r.draw(t.states, ks, angle, target, paths);
    const std::string name = displayName(pc.setup.object) + ", " + pc.setup.surface.name;
    char info[96];
    std::snprintf(info, sizeof info, " (trial 1, %.0f s, moments %.0f s apart): from above", t.duration,
                  ks.size() > 1 ? t.states.times[ks[1]] - t.states.times[ks[0]] : 0.0);
    caption(a, name + info);
    caption(b, "at an angle; target: magenta disc, leader's path magenta" +
                   std::string(t.follower_path.empty() ? "" : ", follower's white"));
    cv::Mat both;
    cv::hconcat(a, b, both);
    const std::string rel = pc.figure_stem + "/" + pc.setup.object.name;
    writeImage(both, out_dir, rel + ".png", written);
    if (with_video) video(r, t.states, angle, target, out_dir, rel, name, written);
  }
}

void writeTrackingPictures(Renderer& r, const TrackingResult& result, const std::string& out_dir, bool with_video,
                           Written& written) {
  if (result.states.empty()) return;
  const View view{result.states.scene.fixtures.empty() ? Vec3::Zero() : Vec3(result.states.scene.fixtures[0].pose.translation()),
                  450, 135, -25};
  writeImage(strip(r, result.states, view, "object tracking"), out_dir, "tracking_errors/frames.png", written);
  if (with_video) video(r, result.states, view, {}, out_dir, "tracking_errors/tracking", "object tracking", written);
}

void writeFollowingPictures(Renderer& r, const FollowingResult& result, const std::string& out_dir, bool with_video,
                            Written& written) {
  if (!result.ramp.states.empty()) {
    const View view{Vec3(0, 90, 25), 400, 10, -15};
    writeImage(strip(r, result.ramp.states, view, "curved ramp"), out_dir, "following_ramp/frames.png", written);
    if (with_video) video(r, result.ramp.states, view, {}, out_dir, "following_ramp/ramp", "curved ramp", written);
  }
  if (!result.dome.empty() && !result.dome.front().states.empty()) {
    const View view{Vec3(0, 0, 60), 400, 120, -30};
    const std::string title = result.dome.front().name;
    writeImage(strip(r, result.dome.front().states, view, title), out_dir, "following_dome/frames.png", written);
    if (with_video) video(r, result.dome.front().states, view, {}, out_dir, "following_dome/dome_0", title, written);
  }
}

}  // namespace lieservo::sim::render
