file(GLOB_RECURSE _sources ${SRC}/*.java)
string(REPLACE ";" "\n" _text "${_sources}")
file(WRITE ${OUT} "${_text}\n")
