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
//
// Deferred messages (mrp_publish_deferred, mrp_flush): each roscpp publish wakes roscpp's poll
// thread twice (the socket's POLLOUT is switched on, the message written, POLLOUT switched off, each
// change signalled through a pipe) and costs one send(2): ~30 us of CPU for an 8-byte /clock, more
// than half a physics step. The C loop's batches of steps hand their /clock messages to
// mrp_publish_deferred, which only appends the message, framed as TCPROS frames it (4-byte length,
// then the bytes), to the publisher's pending frames; mrp_flush (after the batch) publishes all but
// the last pending frame as one roscpp message whose bytes are those frames, then the last one as a
// message of its own, so that a latched topic keeps the last message alone for the next subscriber.
// On the wire the subscriber reads the same frames in the same order as from one publish per message
// (TCP keeps no message boundaries); only fewer writes carry them. mrp_publish first flushes what is
// pending, so messages leave in the order they were handed over whichever entry point took them.
//
// Latching is done here, not by roscpp: roscpp's latch hands the newest message to a new subscriber
// at once, while the messages published just before it still wait in the publication's queue for
// roscpp's poll thread, which then sends them to the new subscriber too, after the newer one. On
// /clock that is time going back at a node's start (8 of 200 subscribers of a fast /clock saw it),
// and a rospy Timer whose sleep sees time go back dies with ROSTimeMovedBackwardsException. Here a
// new subscriber gets the last message from the connect callback, as roscpp's latch does it, but
// only once no message went out for kQuiet seconds (by then the queue has left: a paused
// simulation, a topic published now and then); a subscriber that comes while messages flow gets the
// next one, and no copy of an older one. The topic is advertised a second time with roscpp's latch
// on, and nothing is published through that one: the connection header then says "latching", so a
// rospy subscriber keeps the connection's last message for a second subscription of its process
// (rospy shares one connection per topic), as it does for a latched topic.
#include <algorithm>
#include <ros/publication.h>
#include <ros/ros.h>
#include <ros/topic_manager.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace modrob {
struct RawMessage {
  std::string md5, datatype, definition;
  const uint8_t* data = nullptr;   // the serialised message, without rospy's 4-byte length prefix
  uint32_t size = 0;
};

// Whole TCPROS frames (each a 4-byte little-endian length, then a message of the type `type`
// describes), published as they are
struct RawFrames {
  const RawMessage* type = nullptr;
  const uint8_t* data = nullptr;
  uint32_t size = 0;
};
}  // namespace modrob

namespace ros {
namespace message_traits {
template <> struct IsMessage<modrob::RawMessage> : TrueType {};
template <> struct IsMessage<modrob::RawFrames> : TrueType {};
template <> struct MD5Sum<modrob::RawFrames> {
  static const char* value(const modrob::RawFrames& m) { return m.type->md5.c_str(); }
  static const char* value() { return "*"; }
};
template <> struct DataType<modrob::RawFrames> {
  static const char* value(const modrob::RawFrames& m) { return m.type->datatype.c_str(); }
  static const char* value() { return "*"; }
};
template <> struct Definition<modrob::RawFrames> {
  static const char* value(const modrob::RawFrames& m) { return m.type->definition.c_str(); }
  static const char* value() { return ""; }
};
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
// the frames are the serialised bytes, length prefixes included: nothing is added in front
template <> inline SerializedMessage serializeMessage<modrob::RawFrames>(const modrob::RawFrames& m) {
  SerializedMessage out;
  out.num_bytes = m.size;
  out.buf.reset(new uint8_t[m.size]);
  std::memcpy(out.buf.get(), m.data, m.size);
  out.message_start = out.buf.get() + 4;
  return out;
}
}  // namespace serialization
}  // namespace ros

namespace {
// Deferred messages beyond this many bytes are flushed at once (a batch of steps stays far below)
const size_t kMaxPending = 64 * 1024;

// A latched topic's new subscriber gets the last message once none went out for this long (s)
const double kQuiet = 0.2;
// ... and the connect callback looks again this often (s) whether one went out meanwhile
const double kPoll = 0.005;

double monotonic_now() {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// What the connect callback shares with the C calls (it may run after mrp_unadvertise: it holds
// the Handle through a weak pointer)
struct Handle {
  ros::Publisher pub;
  // the topic's roscpp publication, for its subscriber count (see mrp_num_subscribers)
  ros::PublicationPtr publication;
  ros::Publisher latch_flag;       // latched topics: advertised latched, never published through
  modrob::RawMessage msg;
  std::mutex lock;                 // pending frames, the order of the publishes, the latched copy
  std::vector<uint8_t> pending;    // deferred messages as TCPROS frames
  size_t last = 0;                 // offset of the last pending frame
  bool latch = false;
  // latched topics only: the last message published, how many so far and when the last went out
  std::vector<uint8_t> latched;
  uint64_t published = 0;
  double published_at = -1e9;      // monotonic_now()
};

// Publish one message (h->lock held), remembering it for a latched topic's next subscriber
void publish_one_locked(Handle* h, const uint8_t* data, uint32_t size) {
  h->msg.data = data;
  h->msg.size = size;
  h->pub.publish(h->msg);
  h->msg.data = nullptr;
  if (!h->latch) return;
  h->latched.assign(data, data + size);
  h->published += 1;
  h->published_at = monotonic_now();
}

// Publish the pending frames (h->lock held): all but the last as one roscpp message, the last alone
void flush_locked(Handle* h) {
  if (h->pending.empty()) return;
  if (h->last > 0) {
    modrob::RawFrames frames;
    frames.type = &h->msg;
    frames.data = h->pending.data();
    frames.size = static_cast<uint32_t>(h->last);
    h->pub.publish(frames);
  }
  publish_one_locked(h, h->pending.data() + h->last + 4,
                     static_cast<uint32_t>(h->pending.size() - h->last - 4));
  h->pending.clear();
  h->last = 0;
}

// A subscriber came to a latched topic (roscpp's callback thread): once no message went out for
// kQuiet seconds, it gets the last one; a message published meanwhile reaches it anyway
void on_connect(const std::weak_ptr<Handle>& weak, const ros::SingleSubscriberPublisher& sub) {
  uint64_t seen = 0;
  bool first = true;
  while (true) {
    double wait;
    {
      std::shared_ptr<Handle> h = weak.lock();
      if (!h) return;
      std::lock_guard<std::mutex> guard(h->lock);
      if (!h->pub || h->latched.empty()) return;
      if (first) seen = h->published;
      else if (h->published != seen) return;
      first = false;
      wait = h->published_at + kQuiet - monotonic_now();
      if (wait <= 0.0) {
        h->msg.data = h->latched.data();
        h->msg.size = static_cast<uint32_t>(h->latched.size());
        sub.publish(h->msg);
        h->msg.data = nullptr;
        return;
      }
    }
    // in short sleeps: while messages flow (every subscriber of /clock) the callback ends at the
    // next one, within kPoll, and does not hold up the callbacks of other topics behind it
    std::this_thread::sleep_for(std::chrono::duration<double>(std::min(wait, kPoll)));
  }
}

// The C calls' handle: a heap std::shared_ptr<Handle> (the connect callback holds a weak one)
Handle* handle_of(void* handle) {
  return handle ? static_cast<std::shared_ptr<Handle>*>(handle)->get() : nullptr;
}

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
    auto h = std::make_shared<Handle>();
    h->msg.md5 = md5;
    h->msg.datatype = datatype;
    h->msg.definition = definition;
    h->latch = latch != 0;
    ros::AdvertiseOptions ops(topic, queue_size > 0 ? queue_size : 1, md5, datatype, definition);
    ops.latch = false;              // latched here (see the top of this file)
    if (h->latch) {
      ros::AdvertiseOptions flag = ops;
      flag.latch = true;
      h->latch_flag = g_nh->advertise(flag);
      std::weak_ptr<Handle> weak = h;
      ops.connect_cb = [weak](const ros::SingleSubscriberPublisher& sub) { on_connect(weak, sub); };
    }
    h->pub = g_nh->advertise(ops);
    if (!h->pub) { g_error = std::string("could not advertise ") + topic; return nullptr; }
    h->publication = ros::TopicManager::instance()->lookupPublication(h->pub.getTopic());
    return new std::shared_ptr<Handle>(h);
  } catch (const std::exception& e) {
    g_error = e.what();
    return nullptr;
  }
}

// Publish ``size`` bytes (the serialised message, no length prefix), after any deferred ones.
int mrp_publish(void* handle, const uint8_t* data, uint32_t size) {
  Handle* h = handle_of(handle);
  if (!h || !h->pub) return -1;
  std::lock_guard<std::mutex> guard(h->lock);
  flush_locked(h);
  publish_one_locked(h, data, size);
  return 0;
}

// As mrp_publish, but the message waits (copied) for the next mrp_flush or mrp_publish.
int mrp_publish_deferred(void* handle, const uint8_t* data, uint32_t size) {
  Handle* h = handle_of(handle);
  if (!h || !h->pub) return -1;
  std::lock_guard<std::mutex> guard(h->lock);
  if (h->pending.size() + 4 + size > kMaxPending) flush_locked(h);
  size_t off = h->pending.size();
  h->pending.resize(off + 4 + size);
  uint8_t* p = h->pending.data() + off;
  p[0] = static_cast<uint8_t>(size);              // TCPROS: little-endian uint32 length
  p[1] = static_cast<uint8_t>(size >> 8);
  p[2] = static_cast<uint8_t>(size >> 16);
  p[3] = static_cast<uint8_t>(size >> 24);
  if (size) std::memcpy(p + 4, data, size);
  h->last = off;
  return 0;
}

// Publish the deferred messages now.
int mrp_flush(void* handle) {
  Handle* h = handle_of(handle);
  if (!h || !h->pub) return -1;
  std::lock_guard<std::mutex> guard(h->lock);
  flush_locked(h);
  return 0;
}

// The topic's subscribers: the count ros::Publisher::getNumSubscribers gives (the publication's
// subscriber links), read from the publication itself. getNumSubscribers finds the publication by
// its name under roscpp's lock of all advertised topics, which roscpp's poll thread holds while it
// writes the queued messages of every topic to their sockets: called at the simulation's stops,
// right after the states or /clock went out, the call waited for those writes. The publication's
// own lock is held only while its links change or its own messages are handed to them.
int mrp_num_subscribers(void* handle) {
  Handle* h = handle_of(handle);
  if (!h || !h->pub || !h->publication || h->publication->isDropped()) return 0;
  return static_cast<int>(h->publication->getNumSubscribers());
}

void mrp_unadvertise(void* handle) {
  Handle* h = handle_of(handle);
  if (!h) return;
  {
    std::lock_guard<std::mutex> guard(h->lock);
    if (h->pub) flush_locked(h);
    h->pub.shutdown();
    h->latch_flag.shutdown();
    h->publication.reset();
  }
  delete static_cast<std::shared_ptr<Handle>*>(handle);
}

// ---- /clock -----------------------------------------------------------------------------------
// A ticker publishes rosgraph_msgs/Clock on a publisher at simulated times it is given: at every
// call, or (period > 0) at most once per `period` seconds of the wall clock (CLOCK_MONOTONIC, the
// clock of Python's time.monotonic), never twice for one simulated time. The World's native
// stretches call mrp_clock_observe after every step (World.set_step_observer); the node's Python
// steps call mrp_clock_tick. The messages are deferred (mrp_flush after a stretch sends them in
// one write). The 8 bytes are rospy's for the Clock that StatePublishers.publish_clock builds.
struct ClockTicker {
  void* h;
  double period;
  double last_wall;
  double last_t;
};

void* mrp_clock_new(void* handle, double period) {
  if (!handle) return nullptr;
  return new ClockTicker{handle, period, -1e9, std::nan("")};
}

void mrp_clock_free(void* ticker) { delete static_cast<ClockTicker*>(ticker); }

void mrp_clock_set_period(void* ticker, double period) {
  static_cast<ClockTicker*>(ticker)->period = period;
}

double mrp_clock_last_t(void* ticker) { return static_cast<ClockTicker*>(ticker)->last_t; }

int mrp_clock_tick(void* ticker, double t) {
  ClockTicker* c = static_cast<ClockTicker*>(ticker);
  if (!c || t == c->last_t) return 0;
  if (c->period > 0.0) {
    double now = monotonic_now();
    if (now - c->last_wall < c->period) return 0;
    c->last_wall = now;
  }
  double secs = static_cast<double>(static_cast<long long>(t));
  long long nsecs = static_cast<long long>(std::nearbyint((t - secs) * 1e9));   // Python's round()
  long long whole = static_cast<long long>(secs);
  if (nsecs >= 1000000000LL) {
    whole += 1;
    nsecs -= 1000000000LL;
  }
  uint32_t buf[2] = {static_cast<uint32_t>(whole), static_cast<uint32_t>(nsecs)};   // little-endian
  mrp_publish_deferred(c->h, reinterpret_cast<const uint8_t*>(buf), 8);
  c->last_t = t;
  return 1;
}

// the World's step observer (physics/native: mr_observer_fn)
void mrp_clock_observe(void* ticker, double t) { mrp_clock_tick(ticker, t); }

void mrp_shutdown() {
  if (!g_nh) return;
  if (g_spinner) { g_spinner->stop(); delete g_spinner; g_spinner = nullptr; }
  delete g_nh;
  g_nh = nullptr;
  ros::shutdown();
}
}
