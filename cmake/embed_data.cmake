# Turns the data tables under data/ into one C++ source file, so the library carries them and
# the executable works from any directory (data/README.md). Run as a script:
#   cmake -DDATA_DIR=<repo>/data -DOUTPUT=<file.cpp> -P embed_data.cmake
# Every *.csv and *.ocio file becomes an entry {path relative to data/, contents}.
if(NOT DATA_DIR OR NOT OUTPUT)
  message(FATAL_ERROR "embed_data.cmake needs -DDATA_DIR=... and -DOUTPUT=...")
endif()

file(GLOB_RECURSE data_files RELATIVE ${DATA_DIR} ${DATA_DIR}/*.csv ${DATA_DIR}/*.ocio)
list(SORT data_files)

# A raw string literal carries the text unchanged; its delimiter must not occur in any file.
set(delimiter "glintscope_data")
set(entries "")
foreach(relative_path IN LISTS data_files)
  file(READ ${DATA_DIR}/${relative_path} contents)
  string(FIND "${contents}" ")${delimiter}\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "data/${relative_path} contains the raw-string delimiter ${delimiter}")
  endif()
  string(APPEND entries "        {\"${relative_path}\", R\"${delimiter}(${contents})${delimiter}\"},\n")
endforeach()

set(source "// Generated from data/ by cmake/embed_data.cmake: do not edit.
#include \"core/embedded_data.hpp\"

namespace glintscope {

const std::vector<EmbeddedFile>& embedded_data_files() {
    static const std::vector<EmbeddedFile> files = {
${entries}    };
    return files;
}

}  // namespace glintscope
")

# Rewrite only on change, so an unchanged table does not recompile the library.
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} previous)
  if(previous STREQUAL source)
    return()
  endif()
endif()
file(WRITE ${OUTPUT} "${source}")
