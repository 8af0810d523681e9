// The capture log as CSV (gportctl captures --csv's bytes: both are
// libgport-client's writer, gport/client/capture_files.hpp) or GeoJSON (the
// captures with a position), streamed in chunks, one gportd page at a time:
// memory holds one page, however long the log.
#include <boost/asio/write.hpp>
#include <boost/beast/http/chunk_encode.hpp>
#include <nlohmann/json.hpp>

#include "gport/client/capture_files.hpp"
#include "gport/contract/names.hpp"
#include "gport/web/limits.hpp"
#include "http_session.hpp"

namespace gport::web {
namespace {

using nlohmann::json;
namespace beast = boost::beast;

const json& member(const json& object, const char* key) {
    static const json kNull;
    if (!object.is_object()) {
        return kNull;
    }
    const auto it = object.find(key);
    return it == object.end() ? kNull : *it;
}

// A capture as libgport-client's writer reads it (gportctl's CSV is the same).
std::string text_of(const json& capture) {
    return capture.dump(-1, ' ', false, json::error_handler_t::replace);
}

class Download : public std::enable_shared_from_this<Download> {
  public:
    Download(std::shared_ptr<HttpSession> session, const Request& request, bool geojson)
        : session_(std::move(session)),
          geojson_(geojson),
          keep_alive_(request.keep_alive()),
          request_(request.method(), request.target(), request.version()) {
        request_.keep_alive(keep_alive_);
    }

    void fetch() {
        const json params = {{"since", since_}, {"limit", kCapturesPageSize}};
        session_->context().gateway.read(
            contract::method::kCaptures, params.dump(),
            [self = shared_from_this()](std::optional<client::Error> error,
                                        const std::string& result) {
                self->on_page(error, result);
            });
    }

  private:
    void on_page(const std::optional<client::Error>& error, const std::string& result) {
        const auto page = error ? json() : json::parse(result, nullptr, false);
        if (!member(page, "captures").is_array()) {
            if (!started_) {
                session_->send(error_response(request_, http::status::bad_gateway,
                                              error ? error->message() : "gportd's page is bad",
                                              error ? std::optional(error->code()) : std::nullopt));
            } else {
                session_->finish(false);  // cut short: no last chunk
            }
            return;
        }
        std::string text = started_ ? "" : head();
        for (const auto& capture : page["captures"]) {
            text += geojson_ ? separated(client::capture_geojson_feature(text_of(capture)))
                             : client::capture_csv_row(text_of(capture));
        }
        more_ = member(page, "more") == true && member(page, "next").is_number_unsigned();
        since_ = more_ ? page["next"].get<std::uint64_t>() : since_;
        text += more_ || !geojson_ ? "" : client::captures_geojson_tail();
        if (!started_) {
            start(std::move(text));
        } else {
            write(std::move(text));
        }
    }

    std::string head() const {
        return geojson_ ? client::captures_geojson_head() : client::captures_csv_header();
    }

    std::string separated(std::string f) {
        if (f.empty()) {
            return f;
        }
        return std::exchange(first_feature_, false) ? f : "," + f;
    }

    void start(std::string text) {
        started_ = true;
        header_.version(request_.version());
        header_.result(http::status::ok);
        header_.set(http::field::content_type,
                    geojson_ ? "application/geo+json" : "text/csv; charset=utf-8");
        header_.set(http::field::content_disposition, geojson_
                                                          ? "attachment; filename=captures.geojson"
                                                          : "attachment; filename=captures.csv");
        header_.set(http::field::cache_control, "no-store");
        header_.keep_alive(keep_alive_);
        header_.chunked(true);
        serializer_.emplace(header_);
        session_->stream().expires_after(kHttpIdleTimeout);
        http::async_write_header(session_->stream(), *serializer_,
                                 [self = shared_from_this(), text = std::move(text)](
                                     beast::error_code ec, std::size_t) mutable {
                                     if (ec) {
                                         self->session_->finish(false);
                                         return;
                                     }
                                     self->write(std::move(text));
                                 });
    }

    void write(std::string text) {
        chunk_ = std::move(text);
        session_->stream().expires_after(kHttpIdleTimeout);
        auto next = [self = shared_from_this()](beast::error_code ec, std::size_t) {
            if (ec) {
                self->session_->finish(false);
            } else if (self->more_) {
                self->fetch();
            } else {
                self->last();
            }
        };
        if (chunk_.empty()) {
            next({}, 0);
            return;
        }
        boost::asio::async_write(session_->stream(), http::make_chunk(boost::asio::buffer(chunk_)),
                                 std::move(next));
    }

    void last() {
        boost::asio::async_write(session_->stream(), http::make_chunk_last(),
                                 [self = shared_from_this()](beast::error_code ec, std::size_t) {
                                     self->session_->finish(!ec && self->keep_alive_);
                                 });
    }

    std::shared_ptr<HttpSession> session_;
    bool geojson_;
    bool keep_alive_;
    Request request_;
    std::uint64_t since_ = 0;
    bool more_ = false;
    bool started_ = false;
    bool first_feature_ = true;
    std::string chunk_;
    http::response<http::empty_body> header_;
    std::optional<http::response_serializer<http::empty_body>> serializer_;
};

}  // namespace

void download_captures(const std::shared_ptr<HttpSession>& session, const Request& request,
                       bool geojson) {
    std::make_shared<Download>(session, request, geojson)->fetch();
}

}  // namespace gport::web
