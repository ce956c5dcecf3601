// modrob_viz/ClipCamera: RViz's Camera display with near and far clip distances.
//
// rviz::CameraDisplay builds its projection matrix from the CameraInfo with fixed clip planes
// (0.01 m and 100 m). A camera sensor's SDF <clip><near>/<far> must cut the scene where Gazebo
// would, so this display rewrites the depth rows of that matrix, just before each render of its
// panel, from the properties "Near Clip" and "Far Clip" (metres). Ogre derives its frustum
// (culling) from the same matrix, so nothing nearer than near or beyond far is drawn.
#include <OgreCamera.h>
#include <OgreMatrix4.h>
#include <OgreRenderTargetListener.h>

#include <rviz/default_plugin/camera_display.h>
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
  }

  void preRenderTargetUpdate(const Ogre::RenderTargetEvent& evt) override
  {
    rviz::CameraDisplay::preRenderTargetUpdate(evt);
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
  }

private:
  rviz::FloatProperty* near_property_;
  rviz::FloatProperty* far_property_;
};

}  // namespace modrob_viz

#include <pluginlib/class_list_macros.hpp>
PLUGINLIB_EXPORT_CLASS(modrob_viz::ClipCameraDisplay, rviz::Display)
