"""Where the running Python looks for packages under an install prefix.

Debian's own place for /usr (lib/python3/dist-packages), its local one for
/usr/local, else the prefix's site-packages; printed relative to the prefix
(python/CMakeLists.txt runs it when installing).
"""
import os
import sys
import sysconfig

p = os.path.normpath(sys.argv[1])
names = sysconfig.get_scheme_names()
if p == "/usr" and "deb_system" in names:
    path = sysconfig.get_path("platlib", "deb_system")
elif p == "/usr/local" and "posix_local" in names:
    path = sysconfig.get_path("platlib", "posix_local")
else:
    path = sysconfig.get_path("platlib", "posix_prefix",
                              vars={"base": p, "platbase": p})
print(os.path.relpath(path, p))
