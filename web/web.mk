# web/web.mk -- `make web`: the tutorial in the browser (README, "The tutorial in a browser"), included by the
# Makefile.
#
# The page's OBJ reader (web/obj.c) is also compiled natively for tests/test_web_obj.c, which compares it with
# the program's import.
$(B)/tests/test_web_obj: $(B)/web/obj.o
