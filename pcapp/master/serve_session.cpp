#include "serve_session.h"

#include <utility>

namespace mb2co {
namespace master {

using ascii::GatewayError;
using ascii::Request;

namespace {

/// A download goes block-wise (with `set sdo_block 1`) only when longer than
/// this: CANopenNode's CO_CONFIG_SDO_CLI_PST. An upload is always offered
/// as block (with protocol switch threshold 0: see sdo_client.h).
const size_t kBlockDownloadAbove = 21;

}  // namespace

Session::Session(ServeBackend& backend, const SessionLimits& limits, std::function<std::string()> about)
    : backend_(backend),
      limits_(limits),
      about_(std::move(about)),
      framer_(limits.max_line),
      sdo_timeout_ms_(limits.sdo_timeout_ms) {}

Session::~Session() {
  for (Slot& s : slots_)
    if (s.has_ticket) backend_.cancel(s.ticket);
}

void Session::receive(const uint8_t* data, size_t n) {
  framer_.append(data, n);
  pump();
}

void Session::end_of_input() {
  ended_ = true;
  pump();
}

void Session::sent(size_t n) {
  out_.erase(0, n);
  pump();
}

bool Session::wants_input() const {
  return !ended_ && framer_.ready() == 0 && slots_.size() < limits_.max_outstanding &&
         out_.size() < limits_.max_output;
}

bool Session::finished() const {
  return ended_ && framer_.ready() == 0 && !framer_.partial() && slots_.empty();
}

void Session::event(const std::string& line) {
  log_.push_back(line);
  if (log_.size() > limits_.log_lines) {
    log_.pop_front();
    ++log_dropped_;
  }
  if (!events_) return;
  if (out_.size() >= limits_.max_output) {
    ++events_dropped_;
    return;
  }
  out_ += line + "\r\n";
}

void Session::pump() {
  std::string text;
  // Answers known at once leave at once (flush), so only requests that
  // wait for the network count against max_outstanding.
  for (; slots_.size() < limits_.max_outstanding && out_.size() < limits_.max_output; flush()) {
    const ascii::LineFramer::Item item = framer_.next(&text);
    if (item == ascii::LineFramer::Item::kLine) {
      handle(text);
    } else if (item == ascii::LineFramer::Item::kOverlong) {
      handle_overlong(text);
    } else {
      // At the end of input the unfinished last line is answered, once.
      if (!ended_) break;
      const ascii::LineFramer::Item last = framer_.take_partial(&text);
      if (last == ascii::LineFramer::Item::kNothing) break;
      if (last == ascii::LineFramer::Item::kOverlong) {
        handle_overlong(text);
      } else {
        const Request r =
            ascii::parse_request(text, ascii::ParseContext{limits_.net, default_node_, last_seq_});
        if (r.kind == Request::Kind::kEmpty) continue;  // trailing blanks: nothing asked
        answer(ascii::error_line(r.seq, GatewayError::kSyntax));
      }
    }
  }
  flush();
}

void Session::handle_overlong(const std::string& prefix) {
  last_seq_ = ascii::leading_seq(prefix, last_seq_);
  answer(ascii::error_line(last_seq_, GatewayError::kOutOfMemory));
}

void Session::answer(std::string text) {
  slots_.emplace_back();
  slots_.back().text = std::move(text);
  slots_.back().done = true;
}

void Session::done(Slot* slot) {
  slot->done = true;
  slot->has_ticket = false;
  pump();  // its answer leaves when those before it did; more lines may go
}

void Session::flush() {
  while (!slots_.empty() && slots_.front().done) {
    out_ += slots_.front().text;
    slots_.pop_front();
  }
}

void Session::handle(const std::string& line) {
  ascii::ParseContext context;
  context.net = limits_.net;
  context.default_node = default_node_;
  context.last_seq = last_seq_;
  context.max_value_bytes = limits_.max_value;
  const Request r = ascii::parse_request(line, context);
  if (r.seq_given) last_seq_ = r.seq;
  switch (r.kind) {
    case Request::Kind::kEmpty:
      answer("\r\n");
      return;
    case Request::Kind::kError:
      answer(ascii::error_line(r.seq, r.error));
      return;
    case Request::Kind::kRead:
    case Request::Kind::kWrite:
    case Request::Kind::kNmt: {
      slots_.emplace_back();
      Slot* slot = &slots_.back();
      if (r.kind == Request::Kind::kNmt)
        start_nmt(r, slot);
      else
        start_sdo(r, slot);
      return;
    }
    case Request::Kind::kSetNetwork:  // the parser took only our net
      answer(ascii::ok_line(r.seq));
      return;
    case Request::Kind::kSetNode:
      default_node_ = static_cast<int16_t>(r.number);
      answer(ascii::ok_line(r.seq));
      return;
    case Request::Kind::kSetSdoTimeout:
      if (!backend_.sdo_timeout()) {
        answer(ascii::error_line(r.seq, GatewayError::kRequestNotSupported));
        return;
      }
      sdo_timeout_ms_ = r.number;
      answer(ascii::ok_line(r.seq));
      return;
    case Request::Kind::kSetSdoBlock:
      if (r.number == 1 && !backend_.block_transfer()) {
        answer(ascii::error_line(r.seq, GatewayError::kRequestNotSupported));
        return;
      }
      sdo_block_ = r.number == 1;
      answer(ascii::ok_line(r.seq));
      return;
    case Request::Kind::kSetEvents:
      events_ = r.number == 1;
      answer(ascii::ok_line(r.seq));
      return;
    case Request::Kind::kInfo:
      answer(ascii::value_line(r.seq, info_text()));
      return;
    case Request::Kind::kLog:
      answer(log_text());
      return;
    case Request::Kind::kHelp:
      answer(ascii::help_text());
      return;
    case Request::Kind::kHelpDatatype:
      answer(ascii::help_datatype_text());
      return;
  }
}

void Session::start_sdo(const Request& r, Slot* slot) {
  const bool upload = r.kind == Request::Kind::kRead;
  SdoJob job;
  job.node = r.node;
  job.index = r.index;
  job.sub = r.sub;
  job.upload = upload;
  job.data = r.value;
  job.timeout_ms = sdo_timeout_ms_;
  job.block = sdo_block_ && (upload || r.value.size() > kBlockDownloadAbove);
  const uint32_t seq = r.seq;
  const ascii::DataType type = r.type;
  slot->has_ticket = true;
  slot->ticket = backend_.sdo(std::move(job), [this, slot, seq, type, upload](const SdoOutcome& o) {
    if (!o.gateway_error.empty())
      slot->text = ascii::error_line(seq, GatewayError::kInternalState);
    else if (!o.ok)
      slot->text = ascii::abort_line(seq, o.abort_code);
    else if (upload)
      slot->text = ascii::value_line(seq, ascii::format_value(type, o.data.data(), o.data.size()));
    else
      slot->text = ascii::ok_line(seq);
    done(slot);
  });
}

void Session::start_nmt(const Request& r, Slot* slot) {
  const uint32_t seq = r.seq;
  slot->has_ticket = true;
  slot->ticket = backend_.nmt(r.nmt, r.node, [this, slot, seq](const std::string& failure) {
    slot->text = failure.empty() ? ascii::ok_line(seq) : ascii::error_line(seq, GatewayError::kInternalState);
    slot->done = true;
    slot->has_ticket = false;
    pump();
  });
}

std::string Session::log_text() {
  std::string text;
  if (log_dropped_) text += "(" + std::to_string(log_dropped_) + " earlier lines dropped)\n";
  for (const std::string& line : log_) text += line + "\n";
  log_.clear();
  log_dropped_ = 0;
  if (!text.empty()) text.pop_back();  // the last line ends the answer: CR LF
  return text + "\r\n";
}

std::string Session::info_text() const {
  return about_() + ", sdo_timeout " + std::to_string(sdo_timeout_ms_) + " ms, sdo_block " +
         (sdo_block_ ? "1" : "0") + ", events " + (events_ ? "1" : "0") +
         (default_node_ > 0 ? ", node " + std::to_string(default_node_) : std::string());
}

}  // namespace master
}  // namespace mb2co
