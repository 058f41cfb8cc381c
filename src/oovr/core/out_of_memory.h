// How much an out-of-memory error asked for (docs/reliability.md, "Memory").
//
// The readers bound what an input may ask for (limits.h); what still does
// not fit the machine ends in std::bad_alloc, which says nothing. oovr's
// global operator new records the size of the request that failed, so that
// the error can name the input (the caller's part) and how much it needed
// (this part).
#pragma once

#include <cstdint>
#include <string>

namespace oovr {

// "2.0 GB", "12 MB": a size as messages give it.
std::string rough_bytes(uint64_t bytes);

// Bytes of the last allocation through operator new that failed; 0 when none
// has, or where the sanitizers' allocator replaces oovr's operator new.
uint64_t failed_allocation_bytes();
// Whether this build's operator new is oovr's (false under the sanitizers).
bool records_failed_allocations();

// "a request for 2 GB failed, with 3.4 GB of memory in use at the peak": what
// is known of the last failure, for an error message ("" when nothing is).
std::string out_of_memory_detail();

// "out of memory <doing>: <detail>", the error every command gives for
// std::bad_alloc; `doing` names the input ("loading scene 'oa:oa_dm4'").
std::string out_of_memory_message(const std::string& doing);

}  // namespace oovr
