// libFuzzer target: mb2co-master serve's CiA 309-3 command parser
// (pcapp/master/ascii_*.cpp) and a client's session (serve_session.cpp) on
// any bytes, cut into chunks and answered by a backend that says anything
// (data of any length, abort codes, gateway refusals) in any order.
// Invariants (violations abort):
//  - every line gets exactly one answer, each answer ends in one CR LF and
//    holds no other CR or LF (a value never breaks the line);
//  - the session never holds more requests than max_outstanding, and
//    stops taking input at its limits; at the end of input it finishes;
//  - what format_value prints, the parser reads back (integers), base64
//    round-trips.
#include <stddef.h>
#include <stdint.h>

#include <deque>
#include <string>
#include <vector>

#include "ascii_request.h"
#include "ascii_values.h"
#include "fuzz_support.h"
#include "serve_session.h"

using namespace mb2co;
using namespace mb2co::master;

namespace {

/// Answers the session's requests when the fuzzer says so, with its bytes.
class FuzzBackend : public ServeBackend {
 public:
  struct Call {
    Ticket ticket;
    SdoDone sdo;
    NmtDone nmt;
  };
  Ticket sdo(SdoJob, SdoDone done) override {
    calls.push_back(Call{next, std::move(done), nullptr});
    return next++;
  }
  Ticket nmt(uint8_t, uint8_t, NmtDone done) override {
    calls.push_back(Call{next, nullptr, std::move(done)});
    return next++;
  }
  void cancel(Ticket t) override {
    for (auto it = calls.begin(); it != calls.end(); ++it) {
      if (it->ticket == t) {
        calls.erase(it);
        return;
      }
    }
    fuzz::require(false, "a ticket cancelled that was not pending");
  }
  bool block_transfer() const override { return block; }
  bool sdo_timeout() const override { return block; }
  std::string describe() const override { return "fuzz"; }

  /// Answers the pending call `pick` picks with bytes from `data`.
  void answer(uint8_t pick, const uint8_t*& data, size_t& size) {
    if (calls.empty()) return;
    const size_t i = pick % calls.size();
    Call c = std::move(calls[i]);
    calls.erase(calls.begin() + static_cast<long>(i));
    const size_t n = size ? data[0] % 12 : 0;
    SdoOutcome o;
    o.ok = (pick & 0x30) != 0;
    o.abort_code = 0x06020000u + pick;
    if ((pick & 0x30) == 0 && (pick & 0x40)) o.gateway_error = "refused";
    for (size_t k = 1; k <= n && k < size; ++k) o.data.push_back(data[k]);
    const size_t used = n + 1 < size ? n + 1 : size;
    data += used;
    size -= used;
    if (c.sdo) c.sdo(o);
    if (c.nmt) c.nmt(pick & 1 ? std::string() : std::string("refused"));
  }

  std::deque<Call> calls;
  Ticket next = 1;
  bool block = true;
};

size_t count(const std::string& s, const char* what) {
  size_t n = 0;
  for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

void check_values(const uint8_t* data, size_t size) {
  const size_t n = size < 9 ? size : 9;
  const ascii::DataType all[] = {ascii::DataType::kHex,
                                 ascii::DataType::kBoolean,
                                 ascii::DataType::kI8,
                                 ascii::DataType::kI16,
                                 ascii::DataType::kI32,
                                 ascii::DataType::kI64,
                                 ascii::DataType::kU8,
                                 ascii::DataType::kU16,
                                 ascii::DataType::kU32,
                                 ascii::DataType::kU64,
                                 ascii::DataType::kX8,
                                 ascii::DataType::kX16,
                                 ascii::DataType::kX32,
                                 ascii::DataType::kX64,
                                 ascii::DataType::kR32,
                                 ascii::DataType::kR64,
                                 ascii::DataType::kVisibleString,
                                 ascii::DataType::kOctetString,
                                 ascii::DataType::kUnicodeString,
                                 ascii::DataType::kDomain};
  for (const ascii::DataType t : all) {
    // The type's own length (when the input has it) and one that is not.
    const size_t width = ascii::type_size(t);
    for (const size_t len : {width != 0 && width <= n ? width : n, n / 2}) {
      const std::string text = ascii::format_value(t, data, len);
      fuzz::require(text.find_first_of("\r\n") == std::string::npos, "a value printed over two lines");
      if (width == 0 || width != len || t == ascii::DataType::kR32 || t == ascii::DataType::kR64 ||
          (t == ascii::DataType::kBoolean && data[0] > 1))
        continue;
      std::vector<uint8_t> back;
      fuzz::require(ascii::parse_fixed_value(t, text, &back), "a printed integer does not read back");
      fuzz::require(back == std::vector<uint8_t>(data, data + len), "a printed integer reads back otherwise");
    }
  }
  std::vector<uint8_t> back;
  fuzz::require(ascii::decode_base64(ascii::encode_base64(data, size), &back), "base64 does not decode");
  fuzz::require(back == std::vector<uint8_t>(data, data + size), "base64 does not round-trip");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  check_values(data, size);
  const uint8_t mode = data[0];
  ++data;
  --size;

  FuzzBackend backend;
  backend.block = (mode & 0x80) != 0;
  SessionLimits limits;
  limits.max_line = 64 + (mode & 0x3F) * 4;  // small: overlong lines are reached
  limits.max_outstanding = 1 + (mode & 3);
  limits.max_output = 4096;
  limits.max_value = 48;
  size_t lines = 0;
  std::string out;
  std::string tail;  // the input after its last LF
  {
    Session session(backend, limits, [] { return std::string("about"); });
    // Chunks of 1..16 bytes, the length from the byte before each; between
    // chunks the backend answers what the bytes pick.
    const auto drain = [&] {
      fuzz::require(session.output().size() <= limits.max_output + 4096, "output beyond its bound");
      out += session.output();
      session.sent(session.output().size());
    };
    while (size > 0) {
      const size_t chunk = 1 + (data[0] & 0x0F);
      const uint8_t pick = data[0];
      ++data;
      --size;
      if (!session.wants_input()) {
        // Held back: by requests pending (answer one) or by output the
        // client did not read (it reads).
        if (!backend.calls.empty())
          backend.answer(pick, data, size);
        else
          drain();
        continue;
      }
      const size_t n = chunk < size ? chunk : size;
      for (size_t k = 0; k < n; ++k) {
        if (data[k] == '\n') {
          ++lines;
          tail.clear();
        } else {
          tail += static_cast<char>(data[k]);
        }
      }
      session.receive(data, n);
      data += n;
      size -= n;
      fuzz::require(session.outstanding() <= limits.max_outstanding, "more requests held than allowed");
      if (pick & 0x10) backend.answer(pick, data, size);
      if (pick & 0x20) drain();
    }
    session.end_of_input();
    // The client reads every answer, the backend answers everything.
    for (size_t round = 0; !session.finished() || !session.output().empty(); ++round) {
      fuzz::require(round < 100000, "the session did not finish at the end of input");
      const uint8_t* none = nullptr;
      size_t zero = 0;
      if (!backend.calls.empty())
        backend.answer(0x11, none, zero);
      else
        drain();
    }
  }
  fuzz::require(backend.calls.empty(), "a request left pending");
  // The unfinished last line is answered unless it holds nothing.
  ascii::ParseContext c;
  const bool tail_answered =
      tail.size() > limits.max_line || ascii::parse_request(tail, c).kind != ascii::Request::Kind::kEmpty;
  const size_t answers = count(out, "\r\n");
  fuzz::require(answers == lines + (tail_answered ? 1 : 0), "not one answer per line");
  fuzz::require(count(out, "\r") == answers, "a CR not ending an answer");
  fuzz::require(out.empty() || out.compare(out.size() - 2, 2, "\r\n") == 0, "an answer cut short");
  return 0;
}
