// gport-web: the gimbal in a browser (docs/web.md).
#include <string>
#include <vector>

#include "gport/web/run.hpp"

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    return gport::web::run(args);
}
