/* Counts the point-to-point messages and bytes and the collective calls of each MPI rank,
 * through the MPI profiling interface (loaded with LD_PRELOAD), and writes them at
 * MPI_Finalize to $HS_MPI_TRAFFIC.RANK: "messages bytes collectives collective_bytes". */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

static long long messages, bytes, collectives, collective_bytes;

static long long size_of(int count, MPI_Datatype type) {
  int size = 0;
  PMPI_Type_size(type, &size);
  return (long long)count * size;
}

int MPI_Send(const void *buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm) {
  messages++, bytes += size_of(count, type);
  return PMPI_Send(buf, count, type, dest, tag, comm);
}

int MPI_Isend(const void *buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request *req) {
  messages++, bytes += size_of(count, type);
  return PMPI_Isend(buf, count, type, dest, tag, comm, req);
}

int MPI_Rsend(const void *buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm) {
  messages++, bytes += size_of(count, type);
  return PMPI_Rsend(buf, count, type, dest, tag, comm);
}

int MPI_Sendrecv(const void *sbuf, int scount, MPI_Datatype stype, int dest, int stag, void *rbuf, int rcount,
                 MPI_Datatype rtype, int source, int rtag, MPI_Comm comm, MPI_Status *status) {
  messages++, bytes += size_of(scount, stype);
  return PMPI_Sendrecv(sbuf, scount, stype, dest, stag, rbuf, rcount, rtype, source, rtag, comm, status);
}

int MPI_Allreduce(const void *sbuf, void *rbuf, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  collectives++, collective_bytes += size_of(count, type);
  return PMPI_Allreduce(sbuf, rbuf, count, type, op, comm);
}

int MPI_Allgather(const void *sbuf, int scount, MPI_Datatype stype, void *rbuf, int rcount, MPI_Datatype rtype,
                  MPI_Comm comm) {
  collectives++, collective_bytes += size_of(scount, stype);
  return PMPI_Allgather(sbuf, scount, stype, rbuf, rcount, rtype, comm);
}

int MPI_Allgatherv(const void *sbuf, int scount, MPI_Datatype stype, void *rbuf, const int *rcounts, const int *displs,
                   MPI_Datatype rtype, MPI_Comm comm) {
  collectives++, collective_bytes += size_of(scount, stype);
  return PMPI_Allgatherv(sbuf, scount, stype, rbuf, rcounts, displs, rtype, comm);
}

int MPI_Bcast(void *buf, int count, MPI_Datatype type, int root, MPI_Comm comm) {
  collectives++, collective_bytes += size_of(count, type);
  return PMPI_Bcast(buf, count, type, root, comm);
}

int MPI_Barrier(MPI_Comm comm) {
  collectives++;
  return PMPI_Barrier(comm);
}

int MPI_Finalize(void) {
  const char *prefix = getenv("HS_MPI_TRAFFIC");
  if (prefix) {
    int rank = 0;
    PMPI_Comm_rank(MPI_COMM_WORLD, &rank);
    char path[4096];
    snprintf(path, sizeof path, "%s.%d", prefix, rank);
    FILE *f = fopen(path, "w");
    if (f) {
      fprintf(f, "%lld %lld %lld %lld\n", messages, bytes, collectives, collective_bytes);
      fclose(f);
    }
  }
  return PMPI_Finalize();
}
