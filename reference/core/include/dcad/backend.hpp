// dcad::Backend — which twin answered (the CONTRACT's `backend`), as every typed answer says it.
#pragma once

namespace dcad {

/// The exact reference, the certified cascade (exact, or fast's answer marked not certified where no exact tier
/// runs), or the double twin.
enum class Backend { certified, reference, fast };

/// "certified", "reference" or "fast": the CONTRACT's `backend` value.
inline const char* backend_name(Backend b) {
  switch (b) {
    case Backend::certified: return "certified";
    case Backend::reference: return "reference";
    case Backend::fast: return "fast";
  }
  return "?";
}

}  // namespace dcad
