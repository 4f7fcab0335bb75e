#include "net/http_byte_source.h"

#include <algorithm>
#include <cassert>
#include <cstring>

#include "net/http_source_state.h"
#include "net/network_counters.h"

namespace parallax {

using Piece = HttpByteSource::State::Piece;
using Status = Piece::Status;

InputErrorInfo HttpByteSource::State::errorAt(ByteRange range, std::string expected,
                                              std::string found, std::string hint) const {
  return {.file = display_url,
          .byte_offset = range.offset,
          .expected = std::move(expected),
          .found = std::move(found),
          .hint = std::move(hint)};
}

void HttpByteSource::State::pump() {
  if (closing) return;
  const NetClock::time_point now = NetClock::now();
  while (transfers.size() < std::size_t(std::max(options.max_transfers, 1))) {
    // The queued ranges that may start now, and the most urgent of them.
    std::vector<ByteRange> ranges;
    std::size_t seed = 0;
    bool found = false;
    std::optional<NetClock::time_point> earliest_later;
    for (const auto& [range, piece] : pieces) {
      if (piece.status != Status::Queued || !piece.wanted()) continue;
      if (piece.not_before > now) {
        if (!earliest_later || piece.not_before < *earliest_later)
          earliest_later = piece.not_before;
        continue;
      }
      ranges.push_back(range);
      if (!found) {
        seed = ranges.size() - 1, found = true;
        continue;
      }
      const Piece& best = pieces.at(ranges[seed]);
      // A waiting read before any hint; reads in order of arrival; hints in their order.
      const bool better = piece.waiters > 0
                              ? best.waiters == 0 || piece.wait_serial < best.wait_serial
                              : best.waiters == 0 && piece.hint_rank < best.hint_rank;
      if (better) seed = ranges.size() - 1;
    }
    if (!found) {
      if (earliest_later && (!timer_armed || *earliest_later < timer_at)) {
        timer_armed = true;
        timer_at = *earliest_later;
        const auto delay =
            std::chrono::duration_cast<std::chrono::milliseconds>(*earliest_later - now) +
            std::chrono::milliseconds(1);
        client->after(delay, [weak = weak_from_this()] {
          if (const auto self = weak.lock()) {
            std::lock_guard lock(self->mutex);
            self->timer_armed = false;
            self->pump();
          }
        });
      }
      return;
    }
    const MergedRange group = mergeAround(ranges, seed, options.merge);
    const std::uint64_t key = next_transfer++;
    Transfer& transfer = transfers[key];
    transfer.span = group.span;
    for (std::size_t member : group.members) {
      Piece& piece = pieces.at(ranges[member]);
      piece.status = Status::InFlight;
      piece.transfer = key;
      transfer.parts.push_back(ranges[member]);
    }
    ++stats.requests;
    if (transfer.parts.size() > 1) ++stats.merged_requests;
    // The callback locks `mutex`, which this thread holds: it cannot run before the id is kept.
    transfer.client_id = client->submit({.url = url, .range = group.span},
                                        [weak = weak_from_this(), key](HttpResponse&& response) {
                                          if (const auto self = weak.lock())
                                            self->onAnswer(key, std::move(response));
                                        });
  }
}

void HttpByteSource::State::dropUnwanted() {
  std::vector<std::pair<std::uint64_t, ByteRange>> spares;  // by arrival
  std::uint64_t spare_total = 0;
  for (auto it = pieces.begin(); it != pieces.end();) {
    const Piece& piece = it->second;
    if (piece.wanted() || piece.status == Status::InFlight) {
      ++it;
    } else if (piece.status == Status::Done) {
      spares.emplace_back(piece.done_serial, it->first);
      spare_total += it->first.size;
      ++it;
    } else {
      it = pieces.erase(it);
    }
  }
  std::sort(spares.begin(), spares.end());
  for (const auto& [serial, range] : spares) {
    if (spare_total <= options.spare_bytes) break;
    spare_total -= range.size;
    pieces.erase(range);
  }
}

void HttpByteSource::State::cancelUnwanted() {
  for (auto& item : transfers) {
    const std::uint64_t key = item.first;
    Transfer& transfer = item.second;
    if (transfer.cancelling) continue;
    const bool wanted = std::any_of(transfer.parts.begin(), transfer.parts.end(), [&](auto& r) {
      const auto it = pieces.find(r);
      return it != pieces.end() && it->second.transfer == key && it->second.wanted();
    });
    if (!wanted) {
      transfer.cancelling = true;
      client->cancel(transfer.client_id);
    }
  }
}

void HttpByteSource::State::onAnswer(std::uint64_t key, HttpResponse&& response) {
  std::optional<std::uint64_t> store_at;  // where the answer's body goes in the disk cache
  std::shared_ptr<const std::vector<std::byte>> body;
  {
    std::lock_guard lock(mutex);
    const auto found = transfers.find(key);
    assert(found != transfers.end() && "HttpByteSource: an answer to no request");
    const Transfer transfer = std::move(found->second);
    transfers.erase(found);
    stats.bytes_received += response.body.size();

    // The parts still waiting for this request (a part may have been dropped and asked again).
    std::vector<std::map<ByteRange, Piece>::iterator> parts;
    for (const ByteRange& r : transfer.parts) {
      const auto it = pieces.find(r);
      if (it != pieces.end() && it->second.status == Status::InFlight &&
          it->second.transfer == key) {
        parts.push_back(it);
      }
    }
    auto settle = [&] {
      dropUnwanted();
      pump();
      changed.notify_all();
    };

    if (response.cancelled) {
      ++stats.cancelled_requests;
      for (auto it : parts) it->second.status = Status::Queued;
      settle();
      return;
    }

    const ByteRange span = transfer.span;
    if (poisoned) {
      // The version changed under an earlier answer: nothing after that is delivered.
      for (auto it : parts) {
        it->second.status = Status::Failed;
        it->second.error = *poisoned;
        it->second.error.byte_offset = it->first.offset;
      }
      settle();
      return;
    }
    std::optional<InputErrorInfo> failure;
    bool retryable = false, poison = false;
    const RetryDecision decision = options.retry.decide(response.transport, response.status, 1);
    const std::optional<ContentRange> content_range = parseContentRange(response.content_range);
    // The version this answer is of: only what it states is compared (a header a proxy drops
    // is not a change).
    const bool etag_changed =
        !validator.etag.empty() && !response.etag.empty() && response.etag != validator.etag;
    const bool date_changed = validator.etag.empty() && !validator.last_modified.empty() &&
                              !response.last_modified.empty() &&
                              response.last_modified != validator.last_modified;
    const std::string expected_bytes = "bytes " + std::to_string(span.offset) + "-" +
                                       std::to_string(span.end() - 1) + " (an HTTP 206 answer)";
    if (response.transport != TransportError::None || response.status >= 500) {
      retryable = decision == RetryDecision::Retry;
      failure = errorAt(span, expected_bytes, describeFailure(response), hintForFailure(response));
    } else if (etag_changed || date_changed ||
               (content_range && content_range->total && *content_range->total != size)) {
      poison = true;
      const std::string was = etag_changed   ? "ETag " + validator.etag
                              : date_changed ? "Last-Modified " + validator.last_modified
                                             : std::to_string(size) + " bytes";
      const std::string now = etag_changed   ? "ETag " + response.etag
                              : date_changed ? "Last-Modified " + response.last_modified
                                             : std::to_string(*content_range->total) + " bytes";
      failure = errorAt(span, "the version of the file first read (" + was + ")",
                        now + ": the file changed on the server while it was read",
                        "open it again to read the new version");
    } else if (response.status == 200) {
      const bool whole = span.offset == 0 && span.size == size && response.body.size() == size;
      if (!whole) {
        failure = errorAt(span, expected_bytes,
                          "HTTP 200 with the whole file: the server ignores Range requests",
                          "serve the files from a server with HTTP range requests (nginx, "
                          "Apache, object stores and CDNs have them)");
      }
    } else if (response.status == 206) {
      if (!content_range || !content_range->range || *content_range->range != span) {
        failure = errorAt(span, expected_bytes,
                          "Content-Range " + quoteInput(response.content_range, 60));
      } else if (response.body.size() != span.size) {
        // Cut short on the way (a proxy, a dropped connection that still ended cleanly).
        retryable = options.retry.decide(TransportError::Reset, 0, 1) == RetryDecision::Retry;
        failure = errorAt(span, expected_bytes,
                          "a body of " + std::to_string(response.body.size()) + " bytes for " +
                              std::to_string(span.size));
      }
    } else {
      if (response.status == 416) poison = true;  // the file is shorter than at the probe
      failure = errorAt(span, expected_bytes, describeFailure(response), hintForFailure(response));
    }

    if (!failure) {
      body = std::make_shared<const std::vector<std::byte>>(std::move(response.body));
      // One file for the whole answer: a merged request's nodes are found inside it, and one
      // file costs less than one per node (file creation dominates the cache's writes).
      if (validator.usable()) store_at = span.offset;
      for (auto it : parts) {
        Piece& piece = it->second;
        piece.status = Status::Done;
        piece.done_serial = next_done_serial++;
        piece.body = body;
        piece.body_offset = std::size_t(it->first.offset - span.offset);
      }
    } else if (poison) {
      poisoned = *failure;
      for (auto& [range, piece] : pieces) {
        if (piece.status == Status::Queued ||
            (piece.status == Status::InFlight && piece.transfer == key)) {
          piece.status = Status::Failed;
          piece.error = *failure;
          piece.error.byte_offset = range.offset;
        }
      }
    } else {
      const auto retry_after = parseRetryAfter(response.retry_after);
      for (auto it : parts) {
        Piece& piece = it->second;
        ++piece.attempts;
        const bool again = retryable && piece.attempts < options.retry.max_attempts;
        if (again) {
          std::uniform_real_distribution<double> unit(0.0, 1.0);
          piece.status = Status::Queued;
          piece.not_before =
              NetClock::now() + options.retry.delay(piece.attempts, unit(jitter), retry_after);
          ++stats.retries;
          ++networkCounters().retries;
        } else {
          piece.status = Status::Failed;
          piece.error = *failure;
          piece.error.byte_offset = it->first.offset;
          if (retryable || piece.attempts > 1) {
            piece.error.found += " (" + std::to_string(piece.attempts) + " attempts)";
          }
        }
      }
    }
    settle();
  }
  // On the disk after the lock: readers never wait for the cache's writes.
  if (cache && body && store_at) cache->store(url, *store_at, *body);
}

// ---------------------------------------------------------------------------------------------

HttpByteSource::HttpByteSource(std::shared_ptr<HttpClient> client, std::shared_ptr<State> state)
    : client_(std::move(client)), state_(std::move(state)) {}

HttpByteSource::~HttpByteSource() {
  std::unique_lock lock(state_->mutex);
  state_->closing = true;
  for (auto& [range, piece] : state_->pieces) piece.hint_rank = -1;
  for (auto& [key, transfer] : state_->transfers) {
    if (!transfer.cancelling) client_->cancel(transfer.client_id);
    transfer.cancelling = true;
  }
  // Each request's callback runs (as cancelled); after the last, nothing refers to the client.
  state_->changed.wait(lock, [&] { return state_->transfers.empty(); });
}

const std::string& HttpByteSource::name() const {
  return state_->display_url;
}
std::uint64_t HttpByteSource::size() const {
  return state_->size;
}
const std::string& HttpByteSource::version() const {
  return state_->version;
}
const std::string& HttpByteSource::url() const {
  return state_->url;
}
std::span<const std::byte> HttpByteSource::head() const {
  return state_->head;
}

HttpSourceStats HttpByteSource::stats() const {
  std::lock_guard lock(state_->mutex);
  return state_->stats;
}

void HttpByteSource::read(std::uint64_t offset, std::span<std::byte> out,
                          const ReadContext& context) const {
  checkRange(offset, out.size(), context);
  if (out.empty()) return;
  State& s = *state_;
  const ByteRange range{offset, out.size()};
  auto fail = [&](InputErrorInfo info) {
    info.element = std::string(context.element);
    ++networkCounters().failed_reads;
    throw InputError(std::move(info));
  };
  {
    std::lock_guard lock(s.mutex);
    if (s.poisoned) {
      InputErrorInfo info = *s.poisoned;
      info.byte_offset = offset;
      ++s.stats.failed_reads;
      fail(std::move(info));
    }
    if (range.end() <= s.head.size()) {
      std::memcpy(out.data(), s.head.data() + offset, out.size());
      ++s.stats.head_hits;
      return;
    }
  }
  // A range fetched or being fetched for a hint is taken from memory; only then the disk.
  bool fetching = false;
  {
    std::lock_guard lock(s.mutex);
    fetching = s.pieces.count(range) > 0;
  }
  if (!fetching && s.cache && s.cache->read(s.url, offset, out)) {
    std::lock_guard lock(s.mutex);
    ++s.stats.cache_hits;
    s.stats.cache_bytes += out.size();
    ++networkCounters().cache_hits;
    networkCounters().cache_bytes += out.size();
    return;
  }

  std::unique_lock lock(s.mutex);
  auto [it, created] = s.pieces.try_emplace(range);
  Piece& piece = it->second;
  ++piece.waiters;
  if (piece.wait_serial == 0) piece.wait_serial = s.next_wait_serial++;
  s.pump();
  const bool finished = s.changed.wait(lock, context.cancel, [&] {
    return piece.status == Status::Done || piece.status == Status::Failed;
  });
  --piece.waiters;
  if (!finished) {
    if (!piece.wanted()) {
      if (piece.status == Status::InFlight) {
        s.cancelUnwanted();
      } else {
        s.dropUnwanted();
      }
    }
    throw ReadCancelled();
  }
  if (piece.status == Status::Failed) {
    InputErrorInfo info = piece.error;
    if (!piece.wanted()) s.pieces.erase(it);
    ++s.stats.failed_reads;
    fail(std::move(info));
  }
  std::memcpy(out.data(), piece.body->data() + piece.body_offset, out.size());
  // Read once: a node is read again only after it left every cache, and then from the disk.
  if (piece.waiters == 0) s.pieces.erase(it);
}

void HttpByteSource::prefetch(std::span<const ByteRange> ranges) const {
  State& s = *state_;
  std::lock_guard lock(s.mutex);
  if (s.closing || s.poisoned) return;
  for (auto& [range, piece] : s.pieces) piece.hint_rank = -1;
  int rank = 0;
  for (const ByteRange& range : ranges) {
    if (range.size == 0 || range.offset > s.size || range.size > s.size - range.offset) continue;
    if (range.end() <= s.head.size()) continue;
    auto it = s.pieces.find(range);
    if (it == s.pieces.end()) {
      if (s.cache && s.cache->contains(s.url, range)) continue;  // the read takes it from disk
      it = s.pieces.try_emplace(range).first;
    }
    if (it->second.hint_rank < 0) it->second.hint_rank = rank++;
  }
  s.dropUnwanted();
  s.cancelUnwanted();
  s.pump();
}

}  // namespace parallax
