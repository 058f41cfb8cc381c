# cmake -DFILE=F -DREGEX=R -P match.cmake: exits 0 when the text of F matches
# the CMake regular expression R (as CTest's PASS_REGULAR_EXPRESSION would
# match it), non-zero otherwise (tests/cli/expect.sh).
file(READ "${FILE}" text)
if(NOT text MATCHES "${REGEX}")
  message(FATAL_ERROR "no match")
endif()
