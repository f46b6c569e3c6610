#include "serve_server.h"

#include <errno.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "canopen/clock.h"
#include "host/cli.h"

namespace mb2co {
namespace master {

namespace {

/// Bytes taken from a client per read (and per pass while it wants more).
const size_t kReadChunk = 64 * 1024;

}  // namespace

ServeServer::ServeServer(ServeBackend& backend, const ServerLimits& limits, std::ostream& log)
    : backend_(backend), limits_(limits), log_(log), buffer_(kReadChunk) {}

ServeServer::~ServeServer() {
  clients_.clear();  // sessions cancel what is still running
  if (listen_fd_ >= 0) close(listen_fd_);
  if (listen_fd_ >= 0 && !address_.tcp) unlink(address_.path.c_str());
}

Status ServeServer::listen(const ListenAddress& a) {
  Status s = open_listener(a, &listen_fd_, &where_);
  if (s) address_ = a;
  return s;
}

std::string ServeServer::about() const {
  return std::string("mb2co-master ") + cli::version() + " serve: net " +
         std::to_string(limits_.session.net) + ", " + backend_.describe() + ", " +
         std::to_string(clients_.size()) + " of " + std::to_string(limits_.max_clients) + " clients";
}

void ServeServer::event(const std::string& line) {
  history_.push_back(line);
  if (history_.size() > limits_.session.log_lines) history_.pop_front();
  for (auto& c : clients_)
    if (!c->gone) c->session->event(line);
}

void ServeServer::poll_fds(std::vector<pollfd>* fds) {
  fds->push_back(pollfd{listen_fd_, POLLIN, 0});
  for (const auto& c : clients_) {
    short events = 0;
    if (!c->input_ended && c->session->wants_input()) events |= POLLIN;
    if (!c->session->output().empty()) events |= POLLOUT;
    // Without events still there: poll() reports POLLHUP and POLLERR anyway,
    // so a client that is gone is seen while its transfer runs.
    fds->push_back(pollfd{c->fd, events, 0});
  }
}

void ServeServer::on_poll(const pollfd* fds, size_t n, uint32_t now_us) {
  // The clients first, by the order poll_fds() listed them; new ones are
  // appended after.
  for (size_t i = 1; i < n && i - 1 < clients_.size(); ++i) {
    Client& c = *clients_[i - 1];
    const short r = fds[i].revents;
    if (c.gone || c.fd != fds[i].fd) continue;
    if (r & POLLERR) {
      c.gone = true;
      c.why = "connection error";
    } else if (r & POLLHUP) {
      // Both directions closed: the peer can read no answer any more.
      c.gone = true;
      c.why = "gone";
    } else {
      if (r & POLLIN) read_from(c, now_us);
      if ((r & POLLOUT) && !c.gone) write_to(c);
    }
  }
  if (n > 0 && (fds[0].revents & POLLIN)) accept_clients(now_us);
  sweep();
}

void ServeServer::accept_clients(uint32_t now_us) {
  for (;;) {
    sockaddr_storage peer = {};
    socklen_t len = sizeof peer;
    const int fd =
        accept4(listen_fd_, reinterpret_cast<sockaddr*>(&peer), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;  // EAGAIN: none waiting (or a connection that went away)
    if (clients_.size() >= limits_.max_clients) {
      const std::string no = ascii::error_line(0, ascii::GatewayError::kInternalState);
      if (send(fd, no.data(), no.size(), MSG_NOSIGNAL | MSG_DONTWAIT) < 0) {
        // It is closed below either way.
      }
      close(fd);
      log_ << "serve: connection refused: " << limits_.max_clients << " clients already (--max-clients)\n"
           << std::flush;
      continue;
    }
    std::unique_ptr<Client> c(new Client);
    c->fd = fd;
    c->id = next_id_++;
    c->last_input_us = now_us;
    c->session.reset(new Session(backend_, limits_.session, [this] { return about(); }));
    for (const std::string& line : history_) c->session->event(line);  // its first `log`
    clients_.push_back(std::move(c));
    log_ << "serve: client " << clients_.back()->id << " connected (" << clients_.size() << " of "
         << limits_.max_clients << ")\n"
         << std::flush;
  }
}

void ServeServer::read_from(Client& c, uint32_t now_us) {
  while (!c.input_ended && c.session->wants_input()) {
    const ssize_t got = recv(c.fd, buffer_.data(), buffer_.size(), MSG_DONTWAIT);
    if (got > 0) {
      c.last_input_us = now_us;
      c.session->receive(buffer_.data(), static_cast<size_t>(got));
      if (static_cast<size_t>(got) < buffer_.size()) return;  // drained
    } else if (got == 0) {
      c.input_ended = true;
      c.session->end_of_input();
    } else if (errno == EINTR) {
      continue;
    } else {
      if (errno != EAGAIN && errno != EWOULDBLOCK) {
        c.gone = true;
        c.why = std::string("receive failed: ") + strerror(errno);
      }
      return;
    }
  }
}

void ServeServer::write_to(Client& c) {
  while (!c.session->output().empty()) {
    const std::string& out = c.session->output();
    const ssize_t sent = send(c.fd, out.data(), out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (sent > 0) {
      c.session->sent(static_cast<size_t>(sent));
    } else if (sent < 0 && errno == EINTR) {
      continue;
    } else {
      if (sent < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
        c.gone = true;
        c.why = std::string("send failed: ") + strerror(errno);
      }
      return;
    }
  }
}

void ServeServer::process(uint32_t now_us, const CanSink&) {
  for (auto& p : clients_) {
    Client& c = *p;
    if (c.gone) continue;
    if (!c.session->output().empty()) write_to(c);
    if (c.gone) continue;
    if (c.session->finished() && c.session->output().empty()) {
      c.gone = true;
      c.why = "end of input, every answer sent";
    } else if (limits_.idle_ms && !c.input_ended && c.session->outstanding() == 0 &&
               c.session->output().empty() &&
               time_reached(now_us, c.last_input_us + limits_.idle_ms * 1000u)) {
      c.gone = true;
      c.why = "idle for " + std::to_string(limits_.idle_ms) + " ms";
    }
  }
  sweep();
}

void ServeServer::next_deadline(NextDeadline& d) const {
  if (!limits_.idle_ms) return;
  for (const auto& c : clients_)
    if (!c->input_ended && c->session->outstanding() == 0) d.at(c->last_input_us + limits_.idle_ms * 1000u);
}

void ServeServer::sweep() {
  for (size_t i = 0; i < clients_.size();) {
    Client& c = *clients_[i];
    if (!c.gone) {
      ++i;
      continue;
    }
    log_ << "serve: client " << c.id << " closed: " << c.why;
    if (c.session->outstanding()) log_ << " (" << c.session->outstanding() << " requests cancelled)";
    log_ << "\n" << std::flush;
    close(c.fd);
    clients_.erase(clients_.begin() + static_cast<long>(i));  // its session cancels what is pending
  }
}

}  // namespace master
}  // namespace mb2co
