#pragma once
// A run distributed over ranks (issue #6): which blocks this rank owns, and moving
// whole fields between the ranks and between the balanced layout (blocks cut into
// pieces for the rank count) and the case's own layout, in which files are written.
//
// Every rank keeps the geometry of every block (metrics, wall distance); flow fields
// are computed on owned blocks only, and the solver's work arrays exist only there.
// Output: the root gathers the owned blocks' cells (blocking point-to-point messages,
// block by block), assembles the case's layout and writes it as a serial run would;
// restart.h5 therefore does not depend on the rank count, and a run on N ranks
// restarts on M. One writer is enough at this scale (a restart of 10 M cells is
// 0.4 GB); parallel HDF5 would be the next step for the cluster sizes of the roadmap.
#include "mesh/block.hpp"
#include "parallel/communicator.hpp"
#include "physics/flow.hpp"

namespace narwhal {

// Assigns the blocks of `g` to `ranks` ranks (assign_blocks) and marks this rank's.
// With one rank nothing changes (every block is owned).
void distribute(Grid& g, int ranks, int rank);

// Cells (Q, nu, turbulence variables: those the field has) of every block onto the
// root; the other ranks' fields are unchanged. Collective over comm.
void gather_to_root(const Communicator& comm, const Grid& g, FlowField& f);

// Interior cells between the balanced layout `pieces` and the case's layout `whole`
// (blocks matched by Block::parent and its offset, or by name). `to_whole` true:
// pieces -> whole; false: whole -> pieces. nu and the turbulence variables are copied
// when the source has them (the target's turbulence variables are allocated as needed).
void copy_between_layouts(const Grid& pieces, FlowField& f_pieces, const Grid& whole, FlowField& f_whole, bool to_whole);

}  // namespace narwhal
