"""Wheel and rail wear: local wear laws by name and their distribution over a contact patch.

* :mod:`.coefficients`: the laws' coefficients, read from ``railexu/data/wear_rcf.yaml`` (each
  with its source; railexu's assumptions marked there);
* :mod:`.laws`: Archard's law with Jendel's wear map (KTH) and the University of Sheffield
  energy (T gamma / A) function for R8T wheel steel, chosen by name like the creep laws;
* :mod:`.patch`: FASTSIM's traction and slip over the patch and the wear depth per strip
  across it (docs/wear.md).
"""
