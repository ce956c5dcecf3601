// rviz_lighting/DirectionalLight: an Ogre directional light along a direction in the fixed frame.
#include <OgreLight.h>
#include <OgreSceneManager.h>
#include <OgreVector3.h>
#include <pluginlib/class_list_macros.hpp>
#include <rviz/display.h>
#include <rviz/display_context.h>
#include <rviz/properties/color_property.h>
#include <rviz/properties/float_property.h>
#include <rviz/properties/vector_property.h>

namespace rviz_lighting
{
class DirectionalLightDisplay : public rviz::Display
{
public:
  DirectionalLightDisplay()
  {
    direction_ = new rviz::VectorProperty("Direction", Ogre::Vector3(0.0, 0.0, -1.0),
                                          "Direction the light travels, in the fixed frame.", this);
    color_ = new rviz::ColorProperty("Color", QColor(255, 255, 255), "Diffuse colour.", this);
    intensity_ = new rviz::FloatProperty("Intensity", 0.5, "Multiplies the colour (0..1).", this);
    intensity_->setMin(0.0);
    intensity_->setMax(1.0);
  }
  ~DirectionalLightDisplay() override
  {
    if (light_)
      scene_manager_->destroyLight(light_);
  }

protected:
  void onInitialize() override
  {
    light_ = scene_manager_->createLight();
    light_->setType(Ogre::Light::LT_DIRECTIONAL);
    light_->setSpecularColour(Ogre::ColourValue(0.0, 0.0, 0.0));
    light_->setVisible(false);
  }
  void onEnable() override
  {
    apply();
    light_->setVisible(true);
  }
  void onDisable() override
  {
    light_->setVisible(false);
  }
  void update(float, float) override
  {
    apply();
  }

private:
  void apply()
  {
    Ogre::Vector3 d = direction_->getVector();
    if (d.squaredLength() < 1e-12)
    {
      setStatus(rviz::StatusProperty::Error, "Direction", "zero vector: give a direction such as 0; 0; -1");
      light_->setVisible(false);
      return;
    }
    setStatus(rviz::StatusProperty::Ok, "Direction", "ok");
    d.normalise();
    // The fixed frame's orientation in the scene (the scene's root is the fixed frame).
    light_->setDirection(d);
    Ogre::ColourValue c = color_->getOgreColor() * intensity_->getFloat();
    c.a = 1.0;
    light_->setDiffuseColour(c);
    light_->setVisible(isEnabled());
  }
  rviz::VectorProperty* direction_;
  rviz::ColorProperty* color_;
  rviz::FloatProperty* intensity_;
  Ogre::Light* light_ = nullptr;
};
}  // namespace rviz_lighting

PLUGINLIB_EXPORT_CLASS(rviz_lighting::DirectionalLightDisplay, rviz::Display)
