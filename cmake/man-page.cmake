# Writes the man page bristle(1) from the CLI's own help (cmake -P):
#   cmake -DBRISTLE=path/to/bristle -DHELP2MAN=path/to/help2man -DOUT=bristle.1 \
#         -DDATADIR=/usr/local/share -P man-page.cmake
# help2man turns `bristle --help` and `--version` into the page; each command's
# own help (`bristle help COMMAND`: its options and examples) becomes a
# subsection of COMMANDS, so the page covers every subcommand.

cmake_minimum_required(VERSION 3.25)

foreach(var BRISTLE HELP2MAN OUT DATADIR)
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

# The help's examples name files of the source tree; the page is read by
# someone with the install, which has the library and scenes in
# DATADIR/bristle (brushes/, trajectories/, ...), and the other files
# (golden/, scenes/recordings/) not at all: those become plain file names.
function(installed_paths var text)
  string(REGEX REPLACE "scenes/(brushes|trajectories|paintings|sheets|batch)/"
         "${DATADIR}/bristle/\\1/" text "${text}")
  string(REGEX REPLACE "(golden|scenes/recordings)/" "" text "${text}")
  set(${var} "${text}" PARENT_SCOPE)
endfunction()

# roff: a backslash is \e; a line starting with . or ' would be a request.
function(roff_escape var text)
  string(REPLACE "\\" "\\e" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${var} "${text}" PARENT_SCOPE)
endfunction()

# EXAMPLES: the top-level help's examples, one per line as printed (help2man
# would fold them into one paragraph), with installed paths.
string(REGEX MATCH "\nExamples:\n(  [^\n]*\n)+" examples "${top_help}")
string(REGEX REPLACE "^\nExamples:\n" "" examples "${examples}")
installed_paths(examples "${examples}")
roff_escape(examples "${examples}")
string(CONCAT include "[=EXAMPLES]\nThe library and the example scenes are installed in "
  "${DATADIR}/bristle.\n.PP\n.nf\n${examples}.fi\n")

# ENVIRONMENT: every variable bristle reads.
string(APPEND include "[ENVIRONMENT]\n"
  ".TP\n.B BRISTLE_BRUSH_PATH\nColon-separated folders where a brush name (such as round) is "
  "looked up as NAME.json, after the install's ${DATADIR}/bristle/brushes; "
  "bristle brushes lists them all.\n"
  ".TP\n.B BRISTLE_PROGRESS_SECONDS\nWhen standard error is not a terminal, the seconds between "
  "progress lines of a long render (default 60).\n"
  ".TP\n.B BRISTLE_HD_LIBRARY\nThe OpenHaptics libHD.so that record loads for a Phantom "
  "(default: found by the dynamic linker).\n"
  ".TP\n.B SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT, SLURM_ARRAY_TASK_MIN, JOB_COMPLETION_INDEX\n"
  "Pick the shard of bristle batch in a Slurm job array or a Kubernetes Indexed Job "
  "when --shard is not given.\n"
  ".TP\n.B GALLIUM_DRIVER, LP_NUM_THREADS\nMesa's: bristle renders with llvmpipe "
  "(an unknown driver is refused) and sets LP_NUM_THREADS=0 unless it is set.\n")

string(APPEND include "[COMMANDS]\nEach command's own help, as `bristle help COMMAND` prints it.\n")
foreach(name IN LISTS commands)
  execute_process(COMMAND ${BRISTLE} help ${name} OUTPUT_VARIABLE text RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "man-page.cmake: bristle help ${name} failed (${rc})")
  endif()
  installed_paths(text "${text}")
  roff_escape(text "${text}")
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
