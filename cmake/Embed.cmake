# moire_embed(<target> <symbol-prefix> <files...>)
# Turns text files (the .moire standard library, the default scene) into a generated C++
# source with one `moire::embedded::File` per input, so the binary needs no data directory.
function(moire_embed out_var)
  moire_embed_as(embedded_sources files ${ARGN})
  set(${out_var} ${embedded_sources} PARENT_SCOPE)
endfunction()

# moire_embed_as(<out-var> <function> <files...>): the same, as `moire::embedded::<function>()`
# in a source of its own (declared by the code that reads the files: `moire export`'s page).
function(moire_embed_as out_var function)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_${function}.cpp)
  set(inputs ${ARGN})
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DROOT=${PROJECT_SOURCE_DIR} "-DINPUTS=${inputs}"
            -DFUNCTION=${function} -P ${PROJECT_SOURCE_DIR}/cmake/EmbedScript.cmake
    DEPENDS ${inputs} ${PROJECT_SOURCE_DIR}/cmake/EmbedScript.cmake
    COMMENT "Embedding ${function}"
    VERBATIM)
  set(${out_var} ${out} PARENT_SCOPE)
endfunction()
