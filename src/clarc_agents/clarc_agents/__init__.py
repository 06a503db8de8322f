"""clarc_agents: the agents of the CLARC robot (PELEA, Speech, Panel, Person), each a DSR agent
node whose behaviour is declared as grammar rules over the shared graph."""
