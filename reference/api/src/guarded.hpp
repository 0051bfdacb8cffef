// The three error channels of dcad::api (api.hpp), applied once per entry point.
#pragma once

#include "dcad/api.hpp"

#include <new>

namespace dcad::api {

/// f() with its exceptions on the three channels: bad input (io::InputError, naming the file) and usage
/// as they are, a library precondition on the input (std::invalid_argument) prefixed with the file, and
/// anything else an internal error — but running out of memory, which stays std::bad_alloc.
template <class F>
auto guarded(const io::Problem& p, F f) {
  try {
    return f();
  } catch (const io::InputError&) {
    throw;
  } catch (const UsageError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw io::InputError(p.file + ": " + e.what());
  } catch (const InternalError&) {
    throw;
  } catch (const std::bad_alloc&) {  // a resource limit: the CLI says so (exit 4), no internal error
    throw;
  } catch (const std::exception& e) {
    throw InternalError(e.what());
  }
}

}  // namespace dcad::api
