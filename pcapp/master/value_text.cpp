#include "value_text.h"

#include <cstdio>

#include "eds_reader.h"

namespace mb2co {
namespace master {

namespace {
struct Word {
  const char* word;
  eds::DataType type;
};
const Word kWords[] = {
    {"b", eds::DataType::kBoolean},        {"u8", eds::DataType::kUnsigned8},
    {"u16", eds::DataType::kUnsigned16},   {"u24", eds::DataType::kUnsigned24},
    {"u32", eds::DataType::kUnsigned32},   {"u64", eds::DataType::kUnsigned64},
    {"i8", eds::DataType::kInteger8},      {"i16", eds::DataType::kInteger16},
    {"i32", eds::DataType::kInteger32},    {"i64", eds::DataType::kInteger64},
    {"r32", eds::DataType::kReal32},       {"r64", eds::DataType::kReal64},
    {"vs", eds::DataType::kVisibleString}, {"os", eds::DataType::kOctetString},
    {"us", eds::DataType::kUnicodeString}, {"d", eds::DataType::kDomain},
};
}  // namespace

std::optional<eds::DataType> type_of_word(const std::string& word) {
  for (const Word& w : kWords)
    if (word == w.word) return w.type;
  return std::nullopt;
}

const char* type_words() {
  return "b u8 u16 u24 u32 u64 i8 i16 i32 i64 r32 r64 vs os us d";
}

Status resolve_type(const std::string& word, const std::string& eds_path, uint16_t index, uint8_t sub,
                    eds::DataType* type) {
  if (!word.empty()) {
    const auto t = type_of_word(word);
    if (!t)
      return Status::failure("TYPE must be one of " + std::string(type_words()) + ", got \"" + word + "\"");
    *type = *t;
    return Status::ok();
  }
  char where[16];
  std::snprintf(where, sizeof where, "%04Xh/%u", index, sub);
  if (eds_path.empty())
    return Status::failure(std::string("no type for ") + where + ": give TYPE or --eds FILE");
  const eds::ParseResult r = eds::parse_file(eds_path);
  if (!r) return Status::failure(r.error.text());
  const eds::SubObject* s = r.model->find(index, sub);
  if (!s) return Status::failure(eds_path + ": has no " + where);
  *type = s->type;
  return Status::ok();
}

}  // namespace master
}  // namespace mb2co
