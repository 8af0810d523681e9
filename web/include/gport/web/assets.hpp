// The page's files, built into the program from web/www (a generated
// source: web/cmake/embed_www.cmake).
#pragma once

#include <span>
#include <string_view>

namespace gport::web {

struct Asset {
    std::string_view path;  // "index.html", "app.js", "css/site.css"
    std::string_view content_type;
    std::string_view bytes;
    // An HTML file's inline <style>: the SHA-256 of its text, hex (empty
    // without one), for the Content-Security-Policy.
    std::string_view style_sha256;
};

std::span<const Asset> assets();

// The file at `path` (without the leading '/'), or null.
const Asset* find_asset(std::string_view path);

}  // namespace gport::web
