# A subcommand's man page made by help2man from `wearscar SUB --help`
# names the program `wearscar`: its title and NAME line name the page's
# own command instead (cmake -DPAGE=file -DNAME=wearscar-audit -P ...).
file(READ ${PAGE} text)
string(REGEX REPLACE "\n\\.TH WEARSCAR " "\n.TH ${NAME} " text "${text}")
string(TOUPPER "${NAME}" upper)
string(REGEX REPLACE "\n\\.TH [^ ]+ " "\n.TH ${upper} " text "${text}")
string(REGEX REPLACE "\n\\.SH NAME\nwearscar \\\\- " "\n.SH NAME\n${NAME} \\\\- "
       text "${text}")
file(WRITE ${PAGE} "${text}")
