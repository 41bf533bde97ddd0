# The AVX2 build of the local fits (kernels/multiquadric_fit_avx2.cpp) must not be able to replace
# any code of the generic build at link time: every symbol it defines with external or weak
# linkage names its renamed namespaces (meshless_avx2, meshless_avx2_Eigen) or the interface
# namespace meshless_mqfit, and it has no static initialiser (which would run AVX2 code at start-up
# on any CPU; a sanitizer's module constructor is allowed with -DSANITIZED=1). Run as:
# cmake -DNM=nm -DOBJ=path/to/multiquadric_fit_avx2.cpp.o [-DSANITIZED=1] -P check_isa_object.cmake
if(NOT EXISTS "${OBJ}")
  message(FATAL_ERROR "no object file ${OBJ}")
endif()
execute_process(COMMAND "${NM}" --defined-only "${OBJ}" OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} failed on ${OBJ}")
endif()
string(REPLACE "\n" ";" lines "${out}")
set(checked 0)
foreach(line IN LISTS lines)
  if(line MATCHES "^[0-9a-fA-F]* ([A-Za-z]) (.*)$")
    set(type "${CMAKE_MATCH_1}")
    set(sym "${CMAKE_MATCH_2}")
    # (a sanitized build adds one: the sanitizer's module constructor, which registers globals)
    if(sym MATCHES "_GLOBAL__sub_I|__static_initialization" AND NOT SANITIZED)
      message(FATAL_ERROR "static initialiser in the AVX2 object: ${sym}")
    endif()
    # lower case (t, d, r, b) is local except u (unique global); V/W weak, T/D/B/R global
    if(type MATCHES "^[TDBRVWGSui]$")
      math(EXPR checked "${checked} + 1")
      # a sanitized -O1 build also leaves type information (UBSan's function checks) and small std::
      # inlines (initializer_list, bad_alloc) out of line as weak symbols: the test build, not the product
      if(SANITIZED AND sym MATCHES "^(_ZTI|_ZTS|_ZNSt|_ZNKSt|_ZSt)")
        continue()
      endif()
      if(NOT sym MATCHES "meshless_avx2|meshless_mqfit" AND NOT sym MATCHES "^(DW.ref.__gxx_personality_v0|__clang_call_terminate)$")
        message(FATAL_ERROR "the AVX2 object defines ${sym} (${type}), which the generic build may define too")
      endif()
    endif()
  endif()
endforeach()
if(checked EQUAL 0)
  message(FATAL_ERROR "no global symbol found in ${OBJ}: nothing checked")
endif()
message(STATUS "${checked} global/weak symbols, all in renamed namespaces")
