"""Hardware-in-the-loop simulator for the fcc flight computer."""
