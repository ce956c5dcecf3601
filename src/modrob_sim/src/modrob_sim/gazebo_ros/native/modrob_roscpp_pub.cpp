// roscpp publishers inside the /gazebo node's Python process (loaded with ctypes by
// modrob_sim.gazebo_ros.native_pub), as moveit_commander runs a roscpp node inside Python.
//
// Why: a rospy publish hands every message to one Python thread per subscriber connection
// (QueuedConnection), which costs ~100 us of CPU per message and subscriber under the GIL, more
// than a physics step. Here Python serialises the message once (rospy's own serialize_message, so
// the bytes are exactly rospy's) and roscpp's transport writes them from its own threads without
// the GIL.
//
// The message travels as raw bytes: RawMessage carries the type's md5sum, datatype and definition
// at run time (as topic_tools::ShapeShifter does), so one library serves every message type.
#include <ros/ros.h>

#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace modrob {
struct RawMessage {
  std::string md5, datatype, definition;
  const uint8_t* data = nullptr;   // the serialised message, without rospy's 4-byte length prefix
  uint32_t size = 0;
};
}  // namespace modrob

namespace ros {
namespace message_traits {
template <> struct IsMessage<modrob::RawMessage> : TrueType {};
template <> struct MD5Sum<modrob::RawMessage> {
  static const char* value(const modrob::RawMessage& m) { return m.md5.c_str(); }
  static const char* value() { return "*"; }
};
template <> struct DataType<modrob::RawMessage> {
  static const char* value(const modrob::RawMessage& m) { return m.datatype.c_str(); }
  static const char* value() { return "*"; }
};
template <> struct Definition<modrob::RawMessage> {
  static const char* value(const modrob::RawMessage& m) { return m.definition.c_str(); }
  static const char* value() { return ""; }
};
}  // namespace message_traits
namespace serialization {
template <> struct Serializer<modrob::RawMessage> {
  template <typename Stream> inline static void write(Stream& stream, const modrob::RawMessage& m) {
    std::memcpy(stream.advance(m.size), m.data, m.size);
  }
  inline static uint32_t serializedLength(const modrob::RawMessage& m) { return m.size; }
};
}  // namespace serialization
}  // namespace ros

namespace {
struct Handle {
  ros::Publisher pub;
  modrob::RawMessage msg;
};
ros::NodeHandle* g_nh = nullptr;
ros::AsyncSpinner* g_spinner = nullptr;
std::string g_error;
}  // namespace

extern "C" {

// Start the roscpp node ``name`` (a plain name; namespace ``ns``) talking to ``master_uri``.
// 0 on success, -1 on failure (mrp_error() says why). Idempotent.
int mrp_init(const char* name, const char* ns, const char* master_uri) {
  if (g_nh) return 0;
  try {
    ros::M_string remap;
    if (master_uri && *master_uri) remap["__master"] = master_uri;
    if (ns && *ns) remap["__ns"] = ns;
    // This node only forwards bytes and needs no time of its own: reading /use_sim_time under
    // another name keeps roscpp from subscribing to /clock (which would make it a subscriber of
    // its own /clock, woken at every message)
    remap["/use_sim_time"] = std::string("/") + name + "/use_sim_time_unused";
    ros::init(remap, name, ros::init_options::NoSigintHandler);
    g_nh = new ros::NodeHandle();
    // roscpp's own services (get_loggers, set_logger_level) answer through the global queue
    g_spinner = new ros::AsyncSpinner(1);
    g_spinner->start();
    return 0;
  } catch (const std::exception& e) {
    g_error = e.what();
    return -1;
  }
}

const char* mrp_error() { return g_error.c_str(); }

// Advertise ``topic`` (fully resolved) with the type's md5sum, name and full definition.
void* mrp_advertise(const char* topic, const char* md5, const char* datatype, const char* definition,
                    int queue_size, int latch) {
  if (!g_nh) { g_error = "mrp_init was not called"; return nullptr; }
  try {
    Handle* h = new Handle();
    h->msg.md5 = md5;
    h->msg.datatype = datatype;
    h->msg.definition = definition;
    ros::AdvertiseOptions ops(topic, queue_size > 0 ? queue_size : 1, md5, datatype, definition);
    ops.latch = latch != 0;
    h->pub = g_nh->advertise(ops);
    if (!h->pub) { g_error = std::string("could not advertise ") + topic; delete h; return nullptr; }
    return h;
  } catch (const std::exception& e) {
    g_error = e.what();
    return nullptr;
  }
}

// Publish ``size`` bytes (the serialised message, no length prefix).
int mrp_publish(void* handle, const uint8_t* data, uint32_t size) {
  Handle* h = static_cast<Handle*>(handle);
  if (!h || !h->pub) return -1;
  h->msg.data = data;
  h->msg.size = size;
  h->pub.publish(h->msg);
  h->msg.data = nullptr;
  return 0;
}

int mrp_num_subscribers(void* handle) {
  Handle* h = static_cast<Handle*>(handle);
  return (h && h->pub) ? static_cast<int>(h->pub.getNumSubscribers()) : 0;
}

void mrp_unadvertise(void* handle) {
  Handle* h = static_cast<Handle*>(handle);
  if (!h) return;
  h->pub.shutdown();
  delete h;
}

void mrp_shutdown() {
  if (!g_nh) return;
  if (g_spinner) { g_spinner->stop(); delete g_spinner; g_spinner = nullptr; }
  delete g_nh;
  g_nh = nullptr;
  ros::shutdown();
}
}
