// modrob_viz/ClipCamera: RViz's Camera display with near and far clip distances, whose rendered
// pixels the renderer can read without a round trip through the X server.
//
// rviz::CameraDisplay builds its projection matrix from the CameraInfo with fixed clip planes
// (0.01 m and 100 m). A camera sensor's SDF <clip><near>/<far> must cut the scene where Gazebo
// would, so this display rewrites the depth rows of that matrix, just before each render of its
// panel, from the properties "Near Clip" and "Far Clip" (metres). Ogre derives its frustum
// (culling) from the same matrix, so nothing nearer than near or beyond far is drawn.
//
// Pixels: with "Capture Pixels" on, each render of the panel is copied (glReadPixels through OGRE,
// RGB, top row first) into a buffer right after it is drawn, before the buffers are swapped; the C
// functions at the end hand it to camera_renderer (ctypes) with a serial number per render.
// The render window can be wider than the image: RViz makes every render window's width even (an
// image 321 px wide is drawn in a 322 px window whose last column the panel clips), so the copy
// takes the image's columns from each row of the render.
//
// Depth: with "Capture Depth" on, the depth buffer of each render is read too (glReadPixels,
// GL_DEPTH_COMPONENT as floats, right after the colour) and turned into metres along the optical
// axis with the near and far planes that render was drawn with: the depth camera's depth image.
// A pixel where nothing was drawn (depth buffer at the far plane) reads +inf.
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <GL/gl.h>

#include <OgrePixelFormat.h>
#include <OgreRenderTarget.h>
#include <OgreCamera.h>
#include <OgreMatrix4.h>
#include <OgreRenderTargetListener.h>

#include <rviz/default_plugin/camera_display.h>
#include <rviz/display_context.h>
#include <rviz/frame_manager.h>
#include <rviz/properties/bool_property.h>
#include <rviz/properties/float_property.h>
#include <rviz/render_panel.h>

namespace modrob_viz
{
class ClipCameraDisplay : public rviz::CameraDisplay
{
public:
  ClipCameraDisplay()
  {
    near_property_ = new rviz::FloatProperty("Near Clip", 0.01f,
                                             "Nothing nearer than this (m) to the camera is drawn.", this);
    near_property_->setMin(1e-4f);
    far_property_ = new rviz::FloatProperty("Far Clip", 100.0f,
                                            "Nothing farther than this (m) from the camera is drawn.", this);
    far_property_->setMin(1e-3f);
    capture_property_ = new rviz::BoolProperty("Capture Pixels", false,
                                               "Copy every render into memory for camera_renderer.", this);
    depth_property_ = new rviz::BoolProperty("Capture Depth", false,
                                             "Also copy every render's depth (metres) for camera_renderer.", this);
  }

  void postRenderTargetUpdate(const Ogre::RenderTargetEvent& evt) override
  {
    if (capture_property_->getBool() && evt.source)
    {
      unsigned int w = evt.source->getWidth(), h = evt.source->getHeight();
      if (w == 0 || h == 0)
        return rviz::CameraDisplay::postRenderTargetUpdate(evt);
      // OGRE makes the window's context current and sets GL_PACK_ALIGNMENT 1 itself (rows
      // tightly packed, w * 3 bytes each), so the read fills exactly w * h * 3 bytes
      pixels_.resize(static_cast<size_t>(w) * h * 3);
      Ogre::PixelBox box(w, h, 1, Ogre::PF_BYTE_RGB, pixels_.data());
      evt.source->copyContentsToMemory(Ogre::Box(0, 0, w, h), box, Ogre::RenderTarget::FB_AUTO);
      if (depth_property_->getBool() && drawn_far_ > drawn_near_ && drawn_near_ > 0.0)
        readDepth(w, h);
      else
        depth_.clear();
      width_ = w;
      height_ = h;
      ++serial_;
    }
    rviz::CameraDisplay::postRenderTargetUpdate(evt);
  }

  // the top-left width x height of the last captured render: its serial (0 = none yet), or -1
  // when the render is not that size (its width may be one more: RViz's even window widths)
  long copyPixels(unsigned char* out, int width, int height) const
  {
    if (serial_ == 0)
      return 0;
    if (width <= 0 || height <= 0 || static_cast<int>(height_) != height ||
        (static_cast<int>(width_) != width && static_cast<int>(width_) != width + 1))
      return -1;
    const size_t row = static_cast<size_t>(width) * 3, stride = static_cast<size_t>(width_) * 3;
    for (size_t y = 0; y < height_; ++y)
      std::memcpy(out + y * row, pixels_.data() + y * stride, row);
    return static_cast<long>(serial_);
  }

  // the depth (m) of the last captured render, like copyPixels; -1 also when it has no depth
  long copyDepth(float* out, int width, int height) const
  {
    if (serial_ == 0)
      return 0;
    if (depth_.size() != static_cast<size_t>(width_) * height_ || width <= 0 || height <= 0 ||
        static_cast<int>(height_) != height ||
        (static_cast<int>(width_) != width && static_cast<int>(width_) != width + 1))
      return -1;
    for (size_t y = 0; y < height_; ++y)
      std::memcpy(out + y * width, depth_.data() + y * width_, sizeof(float) * width);
    return static_cast<long>(serial_);
  }

  long serial() const
  {
    return static_cast<long>(serial_);
  }

  // What the render about to happen shows: the stamp of the image whose pose the camera should
  // have, the frame manager's time (where the frame-locked scene is drawn) and whether the camera
  // really is at the image frame's pose of that stamp (RViz moves it only when a new image comes in,
  // and in exact time sync only when the image's stamp is the sync time).
  void noteRender()
  {
    ++renders_;
    const sensor_msgs::Image::ConstPtr& image = texture_.getImage();
    rviz::FrameManager* fm = context_->getFrameManager();
    drawn_stamp_ = image ? image->header.stamp : ros::Time();
    scene_time_ = fm->getTime();
    pose_ok_ = false;
    if (!image || !render_panel_ || !render_panel_->getCamera())
      return;
    Ogre::Vector3 position;
    Ogre::Quaternion orientation;
    if (!fm->getTransform(image->header.frame_id, image->header.stamp, position, orientation))
      return;
    orientation = orientation * Ogre::Quaternion(Ogre::Degree(180), Ogre::Vector3::UNIT_X);
    const Ogre::Camera* camera = render_panel_->getCamera();
    pose_ok_ = camera->getPosition().distance(position) < 1e-3 &&
               camera->getOrientation().equals(orientation, Ogre::Radian(2e-3));
  }

  // Whether RViz's own tf buffer can place `frame` in the fixed frame at `stamp` (RViz's
  // listener thread can be behind the renderer's: a frame-locked object whose frame it cannot look
  // up at the scene time keeps its previous pose in the render).
  bool canTransform(const std::string& frame, const ros::Time& stamp)
  {
    rviz::FrameManager* fm = context_->getFrameManager();
    const std::shared_ptr<tf2_ros::Buffer> buffer = fm->getTF2BufferPtr();
    return buffer && buffer->canTransform(fm->getFixedFrame(), frame, stamp);
  }

  long drawn(unsigned int* stamps, int* pose_ok) const
  {
    stamps[0] = drawn_stamp_.sec;
    stamps[1] = drawn_stamp_.nsec;
    stamps[2] = scene_time_.sec;
    stamps[3] = scene_time_.nsec;
    *pose_ok = pose_ok_ ? 1 : 0;
    return static_cast<long>(renders_);
  }

  void preRenderTargetUpdate(const Ogre::RenderTargetEvent& evt) override
  {
    rviz::CameraDisplay::preRenderTargetUpdate(evt);
    noteRender();
    drawn_near_ = drawn_far_ = 0.0;  // set below when this render has our planes
    if (!render_panel_ || !render_panel_->getCamera())
      return;
    Ogre::Camera* camera = render_panel_->getCamera();
    if (!camera->isCustomProjectionMatrixEnabled())
      return;  // no CameraInfo yet: RViz's own projection
    double n = near_property_->getFloat();
    double f = far_property_->getFloat();
    if (!(n > 0.0) || !(f > n))
      return;  // the renderer checks the values; keep RViz's planes for nonsense
    Ogre::Matrix4 m = camera->getProjectionMatrix();
    m[2][2] = -(f + n) / (f - n);
    m[2][3] = -2.0 * f * n / (f - n);
    camera->setCustomProjectionMatrix(true, m);
    drawn_near_ = n;
    drawn_far_ = f;
  }

private:
  // The window's depth buffer (the render's context is current here), bottom row first in GL, as
  // metres along the optical axis, top row first: window depth d in [0, 1] is the projection's
  // z_ndc = 2 d - 1, and z = 2 f n / ((f + n) - z_ndc (f - n)).
  void readDepth(unsigned int w, unsigned int h)
  {
    raw_depth_.resize(static_cast<size_t>(w) * h);
    depth_.resize(raw_depth_.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, raw_depth_.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    const double n = drawn_near_, f = drawn_far_;
    const float inf = std::numeric_limits<float>::infinity();
    for (size_t y = 0; y < h; ++y)
    {
      const float* src = raw_depth_.data() + (h - 1 - y) * w;
      float* dst = depth_.data() + y * w;
      for (size_t x = 0; x < w; ++x)
      {
        const double d = src[x];
        dst[x] = d >= 1.0 ? inf : static_cast<float>(2.0 * f * n / ((f + n) - (2.0 * d - 1.0) * (f - n)));
      }
    }
  }

  rviz::FloatProperty* near_property_;
  rviz::FloatProperty* far_property_;
  rviz::BoolProperty* capture_property_;
  rviz::BoolProperty* depth_property_;
  std::vector<unsigned char> pixels_;
  std::vector<float> raw_depth_, depth_;
  double drawn_near_ = 0.0, drawn_far_ = 0.0;
  unsigned int width_ = 0, height_ = 0;
  unsigned long serial_ = 0;
  unsigned long renders_ = 0;
  ros::Time drawn_stamp_, scene_time_;
  bool pose_ok_ = false;
};

}  // namespace modrob_viz

// For camera_renderer (ctypes): `display` is the address of an rviz::Display (sip.unwrapinstance).
extern "C" {
// serial of the last captured render (0 = none yet), -1 if the display is not a ClipCamera
long modrob_viz_clip_camera_serial(void* display)
{
  auto* d = dynamic_cast<modrob_viz::ClipCameraDisplay*>(static_cast<rviz::Display*>(display));
  return d ? d->serial() : -1;
}

// The last render of the display: returns how many renders there were (-1: not a ClipCamera);
// stamps = {image stamp sec, nsec, scene time sec, nsec}; pose_ok = the camera was at the image
// frame's pose of the image's stamp.
long modrob_viz_clip_camera_drawn(void* display, unsigned int* stamps, int* pose_ok)
{
  auto* d = dynamic_cast<modrob_viz::ClipCameraDisplay*>(static_cast<rviz::Display*>(display));
  return d ? d->drawn(stamps, pose_ok) : -1;
}

// 1 when RViz's tf buffer has every one of the `count` frames at (sec, nsec) relative to RViz's
// fixed frame, 0 when not, -1 if the display is not a ClipCamera
int modrob_viz_clip_camera_can_transform(void* display, const char** frames, int count, unsigned int sec,
                                         unsigned int nsec)
{
  auto* d = dynamic_cast<modrob_viz::ClipCameraDisplay*>(static_cast<rviz::Display*>(display));
  if (!d)
    return -1;
  const ros::Time stamp(sec, nsec);
  for (int i = 0; i < count; ++i)
    if (!d->canTransform(frames[i], stamp))
      return 0;
  return 1;
}

// copy the last captured render (RGB, width * height * 3 bytes, top row first) into out; returns
// its serial, 0 if there is none yet, -1 if the display is not a ClipCamera or the size differs
// (a render one column wider than width is cropped)
long modrob_viz_clip_camera_copy(void* display, unsigned char* out, int width, int height)
{
  auto* d = dynamic_cast<modrob_viz::ClipCameraDisplay*>(static_cast<rviz::Display*>(display));
  return d ? d->copyPixels(out, width, height) : -1;
}

// copy the depth of the last captured render (metres along the optical axis, +inf where nothing
// was drawn; width * height floats, top row first) into out; returns its serial (the same as its
// pixels'), 0 if there is none yet, -1 if not a ClipCamera, the size differs or it has no depth
long modrob_viz_clip_camera_copy_depth(void* display, float* out, int width, int height)
{
  auto* d = dynamic_cast<modrob_viz::ClipCameraDisplay*>(static_cast<rviz::Display*>(display));
  return d ? d->copyDepth(out, width, height) : -1;
}
}

#include <pluginlib/class_list_macros.hpp>
PLUGINLIB_EXPORT_CLASS(modrob_viz::ClipCameraDisplay, rviz::Display)
