# moire_embed(<target> <symbol-prefix> <files...>)
# Turns text files (the .moire standard library, the default scene) into a generated C++
# source with one `moire::embedded::File` per input, so the binary needs no data directory.
function(moire_embed out_var)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_sources.cpp)
  set(inputs ${ARGN})
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DROOT=${PROJECT_SOURCE_DIR} "-DINPUTS=${inputs}"
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedScript.cmake
    DEPENDS ${inputs} ${PROJECT_SOURCE_DIR}/cmake/EmbedScript.cmake
    COMMENT "Embedding the standard library"
    VERBATIM)
  set(${out_var} ${out} PARENT_SCOPE)
endfunction()
