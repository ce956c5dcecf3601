// rviz_lighting/AmbientLight: the scene manager's ambient light colour while enabled.
#include <OgreColourValue.h>
#include <OgreSceneManager.h>
#include <pluginlib/class_list_macros.hpp>
#include <rviz/display.h>
#include <rviz/display_context.h>
#include <rviz/properties/color_property.h>

namespace rviz_lighting
{
class AmbientLightDisplay : public rviz::Display
{
public:
  AmbientLightDisplay()
  {
    color_ = new rviz::ColorProperty("Color", QColor(80, 80, 80), "Ambient light colour.", this);
  }

protected:
  void onInitialize() override
  {
    previous_ = scene_manager_->getAmbientLight();
  }
  void onEnable() override
  {
    apply();
  }
  void onDisable() override
  {
    scene_manager_->setAmbientLight(previous_);
  }
  void update(float, float) override
  {
    apply();  // cheap; avoids a moc'd slot per property
  }

private:
  void apply()
  {
    scene_manager_->setAmbientLight(color_->getOgreColor());
  }
  rviz::ColorProperty* color_;
  Ogre::ColourValue previous_;
};
}  // namespace rviz_lighting

PLUGINLIB_EXPORT_CLASS(rviz_lighting::AmbientLightDisplay, rviz::Display)
