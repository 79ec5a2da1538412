#pragma once
/// @file overloaded.hpp
/// @brief One visitor from several lambdas, for std::visit over a kind's variant: a kind added
/// to the variant fails to compile wherever it is not handled.
namespace smokescan {

template <class... Ts>
struct Overloaded : Ts... {
    using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace smokescan
