#pragma once
// A session's render options in its header. `record` writes every option that
// changes the render's pixels (SessionRender, cli/paint_options.h) as a line
// "# --OPTION: VALUE" (docs/formats.md, "Session"); `replay` reads them back
// through the options' own parser (cli/record_command.cpp), so a value in a
// header meets the rules it meets on the command line. An option given to
// `replay` wins over the header's, with a warning when the two differ. A
// header without these lines (an older session) leaves each option its default.

#include <string>
#include <utility>
#include <vector>

#include "cli/paint_options.h"
#include "haptics/session_file.h"

namespace bristle::cli {

// The header lines of the options: option ("--paint") and value, in a fixed
// order, with every number written so that it reads back to the same double.
// --ipopt-option has a line per value (none when there is none). Throws
// kUsage naming the option for a value holding a control character, which
// would break the line.
std::vector<std::pair<std::string, std::string>> sessionRenderHeader(const SessionRender& r);

// The command-line words of the options a session's header records
// ("--paint=cadmium-red", "--impasto"), for their parser. Throws kDataError
// "SESSION: header: --NAME: ..." for a "# --NAME:" line of no render option,
// or an --impasto other than true or false.
std::vector<std::string> sessionRenderWords(const haptics::Session& session,
                                            const std::string& session_path);

// Replay's options: each given on the command line (`given`, with its value
// in `args`) as given, every other as the header records it (`recorded`). A
// given option whose value differs from the header's adds a warning to
// *warnings: "SESSION: --px-per-mm 4 overrides the header's 2". A header that
// records no option (an older session) has nothing to override: no warning.
SessionRender mergeSessionRender(const SessionRender& recorded, const haptics::Session& session,
                                 const SessionRender& args, const std::vector<std::string>& given,
                                 const std::string& session_path,
                                 std::vector<std::string>* warnings);

}  // namespace bristle::cli
