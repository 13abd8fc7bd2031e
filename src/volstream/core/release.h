// Emptying a container so that its memory goes back: `v = {}` does not, for a std::vector (it
// assigns an empty initializer list, and the vector keeps its capacity), nor does clear().
#pragma once

namespace vs {

template <class Container>
void release(Container& c) {
  Container().swap(c);
}

}  // namespace vs
