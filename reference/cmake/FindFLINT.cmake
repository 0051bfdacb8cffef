# FLINT (libflint-dev, LGPL): the exact tier of the reference and the certified cascade (fmpq, issue 26).
# Defines FLINT::FLINT.  Debian's FLINT 2.9 ships neither a CMake package nor a pkg-config file.
find_path(FLINT_INCLUDE_DIR flint/fmpq.h)
find_library(FLINT_LIBRARY flint)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(FLINT REQUIRED_VARS FLINT_LIBRARY FLINT_INCLUDE_DIR)
if(FLINT_FOUND AND NOT TARGET FLINT::FLINT)
  add_library(FLINT::FLINT UNKNOWN IMPORTED)
  set_target_properties(FLINT::FLINT PROPERTIES IMPORTED_LOCATION "${FLINT_LIBRARY}"
                                                INTERFACE_INCLUDE_DIRECTORIES "${FLINT_INCLUDE_DIR}")
endif()
# Arb (libflint-arb-dev, LGPL), FLINT's ball arithmetic: FLINT::ARB when found (the certified tier's balls).
# Debian ships no CMake package for it; its headers sit beside FLINT's.
find_path(FLINT_ARB_INCLUDE_DIR arb.h)
find_library(FLINT_ARB_LIBRARY flint-arb)
if(FLINT_FOUND AND FLINT_ARB_INCLUDE_DIR AND FLINT_ARB_LIBRARY AND NOT TARGET FLINT::ARB)
  add_library(FLINT::ARB UNKNOWN IMPORTED)
  set_target_properties(FLINT::ARB PROPERTIES IMPORTED_LOCATION "${FLINT_ARB_LIBRARY}"
                                              INTERFACE_INCLUDE_DIRECTORIES "${FLINT_ARB_INCLUDE_DIR}"
                                              INTERFACE_LINK_LIBRARIES FLINT::FLINT)
endif()
mark_as_advanced(FLINT_INCLUDE_DIR FLINT_LIBRARY FLINT_ARB_INCLUDE_DIR FLINT_ARB_LIBRARY)
