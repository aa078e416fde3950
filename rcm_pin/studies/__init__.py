"""Studies that combine the generic tools on one mechanism (paper 004's five-bar drive
switching, the 3-RRR platform tracking); they may load mechanisms by name."""
