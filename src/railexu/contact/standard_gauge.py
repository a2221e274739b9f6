"""Standard-gauge dimensions: the one declaration of the defaults that track files, vehicle files
and commands take (a module without imports, so that the command line can show them in its help
without loading the profiles' splines)."""

#: Standard gauge [m] (EN 13848-1: 1435 mm, measured 14 mm below the top of rail).
STANDARD_GAUGE_M = 1.435
#: Flange-back distance of standard-gauge wheelsets [m] (EN 13260: 1360 mm).
STANDARD_FLANGE_BACK_M = 1.360
