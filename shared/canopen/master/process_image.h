// The master's process image: a mirror of its nodes' PDO data, one value per
// (node, index, sub). The caller tells which COB-IDs are a node's TPDOs and
// RPDOs and their mapping (the 1A0xh/160xh entries read from the node by SDO
// or from its EDS/DCF); received TPDOs are decoded into the mirror, values
// set in the mirror are encoded into RPDO frames. Packing is CiA 301's
// (§7.2.2.3): bit-granular, little-endian, entry k starting where k-1 ended;
// dummy entries (0002h-0007h) take their bits but no value.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/od_comm.h"

namespace mb2co {
namespace canopen {

/// One mirrored object. Plain data.
struct ImageEntry {
  uint8_t data[8];      ///< value, little-endian; bits above `bits` are zero
  uint32_t updated_us;  ///< when a TPDO last wrote it (valid when updates > 0)
  uint16_t index;
  uint16_t updates;  ///< TPDO receptions that wrote it (never decrements, saturates)
  uint8_t node_id;   ///< 0: slot free
  uint8_t sub;
  uint8_t bits;  ///< mapped length, 1..64 (the longest of its mappings)

  uint32_t u32() const;
  /// The value sign-extended from `bits` (INTEGERn mapped whole or in part).
  int32_t s32() const;
};

/// When an RPDO (a PDO the master sends to a node) leaves.
enum RpdoTrigger : uint8_t {
  kRpdoOnRequest = 0,  ///< only by send_rpdo()
  kRpdoOnSync,         ///< at every on_sync() (the node's types 0..240)
  kRpdoOnChange,       ///< at the next process() after set() changed a mapped value (254/255)
};

/// One configured PDO of a node. Plain data.
struct ImagePdo {
  static const uint8_t kDummy = 0xFF;  ///< `entry` of a dummy mapping entry
  uint16_t cob_id;
  uint16_t length_errors;        ///< TPDO frames shorter than the mapping (ignored; saturates)
  uint8_t node_id;               ///< 0: slot free
  uint8_t n;                     ///< PDO number at the node, 0-based (TPDO1/RPDO1 = 0)
  uint8_t flags;                 ///< kReceive, trigger, kPending (ProcessImageCore)
  uint8_t count;                 ///< mapping entries
  uint8_t bytes;                 ///< mapped length in bytes (the frame's DLC)
  uint8_t entry[kPdoMaxMapped];  ///< ImageEntry slot of each mapping entry, or kDummy
  uint8_t bits[kPdoMaxMapped];   ///< length of each mapping entry
};

/// The logic over caller-owned arrays (one copy in the image whatever the
/// capacities); use ProcessImage<>, which owns them.
class ProcessImageCore {
 public:
  /// A node's TPDO `n` arrives on `cob_id` carrying `mapping[0..count)`
  /// (32-bit entries: index << 16 | sub << 8 | bits, as in 1A0xh). An earlier
  /// configuration of the same (node, TPDO n) is replaced (objects only it
  /// mapped stay in the mirror, unchanged). False, nothing
  /// changed, for node 0 or > 127, a COB-ID above 7FFh, count 0 or above
  /// kPdoMaxMapped, an entry of 0 bits, more than 64 bits in all, a dummy
  /// entry whose length is not its type's, or no room left (PDO or entry
  /// slots).
  bool configure_tpdo(uint8_t node_id, uint8_t n, uint16_t cob_id, const uint32_t* mapping, uint8_t count);
  /// A node's RPDO `n` (the master sends it) on `cob_id`, same rules.
  bool configure_rpdo(uint8_t node_id, uint8_t n, uint16_t cob_id, const uint32_t* mapping, uint8_t count,
                      RpdoTrigger trigger);

  /// A received frame: true if it is a configured TPDO (consumed). A frame
  /// shorter than the mapping is ignored and counted (ImagePdo::length_errors,
  /// pdo_length_errors(): the master's view of EMCY 8210h); a longer one is
  /// decoded (CiA 301 lets a consumer use the mapped part).
  bool on_frame(const CanFrame& f, uint32_t now_us);

  /// The mirrored object, nullptr when no PDO maps it.
  const ImageEntry* find(uint8_t node_id, uint16_t index, uint8_t sub) const;
  /// Sets a mirrored value (the low `bits` of `value` count). False when no
  /// PDO maps (node, index, sub). An RPDO with kRpdoOnChange mapping it
  /// becomes pending when the value changed.
  bool set(uint8_t node_id, uint16_t index, uint8_t sub, uint32_t value);
  /// The same with the value's bytes (little-endian, `len` <= 8).
  bool set_bytes(uint8_t node_id, uint16_t index, uint8_t sub, const uint8_t* data, uint8_t len);

  /// Encodes RPDO `n` of `node_id` from the mirror and sends it. False when
  /// not configured or the port refused it (counted in send_failures()).
  bool send_rpdo(uint8_t node_id, uint8_t n, const CanSink& sink);
  /// Sends every kRpdoOnSync RPDO (call when the SYNC producer sent one).
  void on_sync(const CanSink& sink);
  /// Sends pending kRpdoOnChange RPDOs; a refused one stays pending.
  void process(uint32_t now_us, const CanSink& sink);
  /// Lowers `d` to now while an RPDO is pending.
  void next_deadline(NextDeadline& d) const;

  /// The configured PDO, nullptr when none: `rpdo` false = a TPDO of the
  /// node (the master receives it), true = an RPDO of the node (it sends).
  const ImagePdo* pdo(uint8_t node_id, uint8_t n, bool rpdo) const;
  uint16_t pdo_length_errors() const { return length_errors_; }
  uint16_t send_failures() const { return send_failures_; }

 protected:
  ProcessImageCore(ImagePdo* pdos, uint8_t max_pdos, ImageEntry* entries, uint8_t max_entries)
      : pdos_(pdos), entries_(entries), max_pdos_(max_pdos), max_entries_(max_entries) {}

 private:
  enum : uint8_t { kReceive = 0x01, kTriggerMask = 0x06, kTriggerShift = 1, kPending = 0x08 };
  bool configure(uint8_t node_id, uint8_t n, uint16_t cob_id, const uint32_t* mapping, uint8_t count,
                 uint8_t flags);
  ImagePdo* find_pdo(uint8_t node_id, uint8_t n, bool rpdo);
  uint8_t find_entry(uint8_t node_id, uint16_t index, uint8_t sub) const;
  bool send(ImagePdo& p, const CanSink& sink);

  ImagePdo* pdos_;
  ImageEntry* entries_;
  uint8_t max_pdos_;
  uint8_t max_entries_;
  uint16_t length_errors_ = 0;
  uint16_t send_failures_ = 0;
};

/// A process image for up to `MaxPdos` PDOs (TPDOs and RPDOs of all nodes
/// together) mapping up to `MaxEntries` distinct objects.
template <uint8_t MaxPdos, uint8_t MaxEntries>
class ProcessImage : public ProcessImageCore {
  static_assert(MaxPdos >= 1 && MaxEntries >= 1 && MaxEntries < ImagePdo::kDummy, "capacities");

 public:
  ProcessImage() : ProcessImageCore(pdo_store_, MaxPdos, entry_store_, MaxEntries) {}
  ProcessImage(const ProcessImage&) = delete;
  ProcessImage& operator=(const ProcessImage&) = delete;

 private:
  ImagePdo pdo_store_[MaxPdos] = {};
  ImageEntry entry_store_[MaxEntries] = {};
};

}  // namespace canopen
}  // namespace mb2co
