# moire_embed(<out-var> <files...>)
# Turns text files (the .moire standard library, the default scene) into a generated C++
# source with one `moire::embedded::File` per input, so the binary needs no data directory.
function(moire_embed out_var)
  moire_embed_as(out moire::embedded compiler/stdlib/Embedded.h ${ARGN})
  set(${out_var} ${out} PARENT_SCOPE)
endfunction()

# moire_embed_as(<out-var> <namespace> <header> <files...>)
# The same into a namespace of its own: `<namespace>::files()`, declared in <header> (with its
# `File` struct), for another set of files (the page of `moire serve`).
function(moire_embed_as out_var namespace header)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_sources.cpp)
  set(inputs ${ARGN})
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DROOT=${PROJECT_SOURCE_DIR} "-DINPUTS=${inputs}"
            -DNAMESPACE=${namespace} -DHEADER=${header}
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedScript.cmake
    DEPENDS ${inputs} ${PROJECT_SOURCE_DIR}/cmake/EmbedScript.cmake
    COMMENT "Embedding ${namespace}"
    VERBATIM)
  set(${out_var} ${out} PARENT_SCOPE)
endfunction()
