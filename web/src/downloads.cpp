// The capture log as CSV (gportctl captures --csv's columns) or GeoJSON
// (the captures with a position), streamed in chunks, one gportd page at a
// time: memory holds one page, however long the log.
#include <boost/asio/write.hpp>
#include <boost/beast/http/chunk_encode.hpp>
#include <ctime>
#include <nlohmann/json.hpp>

#include "gport/contract/names.hpp"
#include "gport/web/limits.hpp"
#include "http_session.hpp"

namespace gport::web {
namespace {

using nlohmann::json;
namespace beast = boost::beast;

std::string number(const json& value) {
    return value.is_number() ? value.dump() : "";
}

// A text cell, quoted, with a leading quote before what a spreadsheet would
// take for a formula.
std::string text_cell(const json& value) {
    std::string cell = value.is_string() ? value.get<std::string>() : number(value);
    if (!cell.empty() && std::string_view("=+-@\t\r").find(cell.front()) != std::string::npos) {
        cell.insert(0, "'");
    }
    std::string out = "\"";
    for (char c : cell) {
        out += c == '"' ? std::string("\"\"") : std::string(1, c);
    }
    return out + "\"";
}

const json& member(const json& object, const char* key) {
    static const json kNull;
    if (!object.is_object()) {
        return kNull;
    }
    const auto it = object.find(key);
    return it == object.end() ? kNull : *it;
}

std::string utc_of(const json& capture) {
    const auto& us = member(capture, "utc_us");
    if (!us.is_number_integer()) {
        return "";
    }
    const auto micros = us.get<std::int64_t>();
    const std::time_t seconds = micros / 1000000;
    std::tm tm{};
    gmtime_r(&seconds, &tm);
    char text[96];
    std::snprintf(text, sizeof(text), "%04d-%02d-%02dT%02d:%02d:%02d.%06lldZ", tm.tm_year + 1900,
                  tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec,
                  static_cast<long long>(micros % 1000000));
    return text;
}

std::string csv_row(const json& capture) {
    std::string row = number(member(capture, "index")) + "," + text_cell(utc_of(capture)) + "," +
                      text_cell(member(capture, "kind"));
    const auto& attitude = member(capture, "attitude");
    for (const char* source : {"imu", "hall"}) {
        for (const char* axis : {"roll", "pitch", "yaw"}) {
            row += "," + number(member(member(attitude, source), axis));
        }
    }
    const auto& meta = member(capture, "meta");
    return row + "," + number(member(meta, "lat")) + "," + number(member(meta, "lon")) + "," +
           number(member(meta, "alt_m")) + "\n";
}

// A GeoJSON feature, or nothing for a capture without a position.
std::string feature(const json& capture) {
    const auto& meta = member(capture, "meta");
    if (!member(meta, "lat").is_number() || !member(meta, "lon").is_number()) {
        return "";
    }
    json coordinates = {meta["lon"], meta["lat"]};
    if (member(meta, "alt_m").is_number()) {
        coordinates.push_back(meta["alt_m"]);
    }
    const json f = {{"type", "Feature"},
                    {"geometry", {{"type", "Point"}, {"coordinates", coordinates}}},
                    {"properties",
                     {{"index", member(capture, "index")},
                      {"utc", utc_of(capture)},
                      {"kind", member(capture, "kind")},
                      {"attitude", member(capture, "attitude")}}}};
    return f.dump(-1, ' ', false, json::error_handler_t::replace);
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
        session_->context().gateway.call(
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
            text += geojson_ ? separated(feature(capture)) : csv_row(capture);
        }
        more_ = member(page, "more") == true && member(page, "next").is_number_unsigned();
        since_ = more_ ? page["next"].get<std::uint64_t>() : since_;
        text += more_ ? "" : (geojson_ ? "]}\n" : "");
        if (!started_) {
            start(std::move(text));
        } else {
            write(std::move(text));
        }
    }

    std::string head() const {
        return geojson_ ? R"({"type":"FeatureCollection","features":[)"
                        : "index,utc,kind,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,"
                          "hall_yaw,lat,lon,alt_m\n";
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
