// Writes an eds::DeviceDescription as CiA 306 text that eds::parse() reads
// back as the same model: sections [FileInfo], [DeviceInfo], the other
// sections as read, the three object lists, every object with its
// sub-objects (compact arrays written out in full), and for a DCF
// [DeviceComissioning]. Values are written with format_value() (eds_value.h);
// ParameterValue where the model has one, $NODEID kept symbolic.
//
// The model is expected to satisfy the invariants of eds_model.h and to hold
// only what a file can say (e.g. a VAR's sub 0 carries the object's name,
// text without line breaks or leading/trailing blanks).
#pragma once
#include <stdint.h>

#include <optional>
#include <string>

#include "eds_model.h"

namespace mb2co {
namespace eds {

/// The model as a file: an EDS when it has no commissioning section.
std::string write_eds(const DeviceDescription& model);

/// The model as the DCF of node `node_id` (1..127): [DeviceComissioning]
/// NodeID = node_id, Baudrate = baudrate_kbit when given (else as the model
/// has it), the model's other commissioning keys kept.
std::string write_dcf(const DeviceDescription& model, uint8_t node_id,
                      std::optional<uint16_t> baudrate_kbit = std::nullopt);

/// What write_dcf() records in the model: its commissioning section with
/// NodeID (and Baudrate) set. parse(write_dcf(m, n, b)) == with_commissioning(m, n, b).
DeviceDescription with_commissioning(DeviceDescription model, uint8_t node_id,
                                     std::optional<uint16_t> baudrate_kbit = std::nullopt);

}  // namespace eds
}  // namespace mb2co
