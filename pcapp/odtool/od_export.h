// Writes an Object Dictionary, from the same constant rows the node runs on,
// as the user's Markdown table (docs/od*.md) or as a CiA 306 EDS file.
#pragma once
#include <string>

#include "canopen/od.h"

namespace mb2co {
namespace odtool {

std::string od_markdown(const canopen::ObjectDictionary& od, const std::string& title);
std::string od_eds(const canopen::ObjectDictionary& od, const std::string& product);
/// The Modbus register map of a gateway OD (maps 2400h–2403h) as Markdown.
std::string register_map_markdown(const canopen::ObjectDictionary& od);

}  // namespace odtool
}  // namespace mb2co
