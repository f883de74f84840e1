# Writes the man page bristle(1) from the CLI's own help (cmake -P):
#   cmake -DBRISTLE=path/to/bristle -DHELP2MAN=path/to/help2man -DOUT=bristle.1 -P man-page.cmake
# help2man turns `bristle --help` and `--version` into the page; each command's
# own help (`bristle help COMMAND`: its options and examples) becomes a
# subsection of COMMANDS, so the page covers every subcommand.

cmake_minimum_required(VERSION 3.25)

foreach(var BRISTLE HELP2MAN OUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "man-page.cmake: -D${var}=... is required")
  endif()
endforeach()

# The commands, as `bristle --help` lists them (the lines under "Subcommands:",
# up to the blank line).
execute_process(COMMAND ${BRISTLE} --help OUTPUT_VARIABLE top_help RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "man-page.cmake: ${BRISTLE} --help failed (${rc})")
endif()
string(REGEX MATCH "\nSubcommands:\n([^\n]+\n)+" block "${top_help}")
string(REGEX MATCHALL "\n  [a-z]+ " lines "${block}")
set(commands "")
foreach(line IN LISTS lines)
  string(STRIP "${line}" line)
  string(REGEX REPLACE " .*" "" name "${line}")
  if(NOT name STREQUAL "help")
    list(APPEND commands ${name})
  endif()
endforeach()
list(LENGTH commands count)
if(count LESS 5)
  message(FATAL_ERROR "man-page.cmake: found only '${commands}' in bristle --help")
endif()

set(include "[COMMANDS]\nEach command's own help, as `bristle help COMMAND` prints it.\n")
foreach(name IN LISTS commands)
  execute_process(COMMAND ${BRISTLE} help ${name} OUTPUT_VARIABLE text RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "man-page.cmake: bristle help ${name} failed (${rc})")
  endif()
  # roff: a backslash is \e; a line starting with . or ' would be a request.
  string(REPLACE "\\" "\\e" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  string(APPEND include ".SS \"bristle ${name}\"\n.nf\n${text}.fi\n")
endforeach()
string(APPEND include "[SEE ALSO]\nThe documentation installed in share/bristle/docs: README.md, and\n"
  "errors.md for the exit codes, limits and the catalogue of hostile inputs.\n")
get_filename_component(out_dir "${OUT}" DIRECTORY)
file(WRITE "${out_dir}/bristle.h2m" "${include}")

execute_process(
  COMMAND ${HELP2MAN} --no-info --section 1
          --name "render brush strokes from 6-DOF stylus motion (Baxter & Lin 2004 brush model)"
          --include "${out_dir}/bristle.h2m" --output "${OUT}" ${BRISTLE}
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "man-page.cmake: help2man failed (${rc})")
endif()
