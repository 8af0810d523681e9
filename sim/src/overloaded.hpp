// The overload-set helper for std::visit with several lambdas.
#pragma once

namespace gport::sim::detail {

template <typename... F>
struct Overloaded : F... {
    using F::operator()...;
};
template <typename... F>
Overloaded(F...) -> Overloaded<F...>;

}  // namespace gport::sim::detail
